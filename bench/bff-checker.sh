#!/usr/bin/env bash
# What BFF's outputs are, as ../shared/tools/checkuv.py sees them: for every row of
# ../shared/reference/bff-cones.tsv, BFF (`bff-command-line IN OUT --nCones=N`, built outside
# this project) runs on the shared mesh and the checker measures its OBJ. Besides the TSV's E
# and angle distortion this records how many cones the checker finds (interior vertices whose uv
# angle sum is not 2 pi), the seam length mismatch, and how much curvature sits away from BFF's
# N strongest cones: the other interior vertices where |2 pi - angle sum| > 1e-3, and the sum of
# it over them, over pi.
#
#   BFF_COMMAND=/path/to/bff-command-line bench/bff-checker.sh [OUT_DIR] > bench/bff-checker.tsv
#
# bench/cones.sh reads bench/bff-checker.tsv: where BFF's output is not a flat metric with N
# cones it says so, and finds how few exact cones of ours beat it.
set -uo pipefail
cd "$(dirname "$0")/.."
out=${1:-build/bff-checker}
shared=${RICCI_SHARED_MESHES:-$PWD/../shared/meshes}
reference=$PWD/../shared/reference/bff-cones.tsv
checkuv=$PWD/../shared/tools/checkuv.py
bff=${BFF_COMMAND:?set BFF_COMMAND to the path of bff-command-line}
mkdir -p "$out"

path_of() {  # mesh name -> file under shared/meshes
  local f
  for f in "$shared/$1".*; do
    [ -f "$f" ] && echo "$f" && return
  done
}

# BFF reads OBJ only: OFF and binary PLY (float x y z, uchar-int triangle lists, as the shared
# ones are) are rewritten as OBJ, same vertices in the same order.
obj_of() {
  local src=$1 name=$2
  case "$src" in
    *.obj) echo "$src"; return ;;
  esac
  /usr/bin/python3 - "$src" "$out/$name.obj" <<'PY' || return 1
import struct, sys
src, dst = sys.argv[1], sys.argv[2]
V, F = [], []
if src.endswith(".off"):
    words = [w for line in open(src) for w in line.split("#")[0].split()]
    nv, nf = int(words[1]), int(words[2])
    at = 4
    V = [words[at + 3 * i: at + 3 * i + 3] for i in range(nv)]
    at += 3 * nv
    for _ in range(nf):
        k = int(words[at])
        F.append([int(x) for x in words[at + 1: at + 1 + k]])
        at += 1 + k
else:
    data = open(src, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode().split("\n")
    assert "format binary_little_endian 1.0" in header
    nv = int(next(h for h in header if h.startswith("element vertex")).split()[2])
    nf = int(next(h for h in header if h.startswith("element face")).split()[2])
    at = end
    for i in range(nv):
        V.append(["%.9g" % x for x in struct.unpack_from("<3f", data, at)])
        at += 12
    for i in range(nf):
        k = data[at]
        F.append(list(struct.unpack_from("<%di" % k, data, at + 1)))
        at += 1 + 4 * k
with open(dst, "w") as out:
    out.writelines("v %s %s %s\n" % tuple(v) for v in V)
    out.writelines("f " + " ".join(str(i + 1) for i in f) + "\n" for f in F)
PY
  echo "$out/$name.obj"
}

printf 'mesh\tcones\tbff_checker_cones\tbff_other_curved_vertices\tbff_other_curvature_over_pi\tbff_seam_mismatch\tbff_E\tbff_angle\tbff_flipped\n'
while IFS=$'\t' read -r name n _; do
  case "$name" in '#'*|mesh|'') continue ;; esac
  src=$(path_of "$name")
  [ -n "$src" ] || continue
  obj=$(obj_of "$src" "$name") || { echo "bff-checker.sh: cannot convert $src" >&2; continue; }
  OPENBLAS_NUM_THREADS=1 "$bff" "$obj" "$out/$name-$n.obj" --nCones="$n" >"$out/$name-$n.log" 2>&1 ||
    { echo "bff-checker.sh: BFF failed on $name $n" >&2; continue; }
  /usr/bin/python3 "$checkuv" "$out/$name-$n.obj" >"$out/$name-$n.check.json"
  /usr/bin/python3 - "$out/$name-$n.obj" "$out/$name-$n.check.json" "$name" "$n" <<'EOF'
import json, math, sys
from collections import Counter
obj, check, name, n = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
V, T, F = [], [], []
for line in open(obj):
    w = line.split()
    if not w:
        continue
    if w[0] == "v":
        V.append(tuple(map(float, w[1:4])))
    elif w[0] == "vt":
        T.append(tuple(map(float, w[1:3])))
    elif w[0] == "f":
        F.append([tuple(int(x) - 1 for x in c.split("/")[:2]) for c in w[1:4]])
sums = [0.0] * len(V)
edges = Counter()
for f in F:
    for k in range(3):
        (v, a), (_, b), (_, c) = f[k], f[(k + 1) % 3], f[(k + 2) % 3]
        ux, uy = T[b][0] - T[a][0], T[b][1] - T[a][1]
        vx, vy = T[c][0] - T[a][0], T[c][1] - T[a][1]
        sums[v] += math.atan2(abs(ux * vy - uy * vx), ux * vx + uy * vy)
        edges[tuple(sorted((f[k][0], f[(k + 1) % 3][0])))] += 1
boundary = {v for e, c in edges.items() if c == 1 for v in e}
curvature = sorted((abs(2 * math.pi - s) for v, s in enumerate(sums) if v not in boundary),
                   reverse=True)
d = json.load(open(check))
# Beyond its N strongest: vertices curved by more than 1e-3 (BFF writes 6 decimals, whose
# rounding alone curves vertices by about 1e-5), and their curvature together.
others = [k for k in curvature[n:] if k > 1e-3]
print(f"{name}\t{n}\t{d['cones']}\t{len(others)}\t{sum(others) / math.pi:.4g}\t"
      f"{d['seam_length_mismatch']:.3g}\t{d['area_distortion_energy']:.4f}\t"
      f"{d['angle_distortion_mean']:.4f}\t{d['flipped']}")
EOF
done <"$reference"
