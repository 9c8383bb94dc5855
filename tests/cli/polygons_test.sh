#!/usr/bin/env bash
# Polygon meshes end to end: `ricci param` (and `ricci batch`, which runs it) on generated quad
# and n-gon meshes writes the input's own faces, in the input's order, with a vt per corner
# (`f v/vt v/vt v/vt v/vt`), the input's vertices unchanged; and ../shared/tools/checkuv.py,
# which splits each polygon as the fan from its first corner, finds no flipped face, seams that
# match to 1e-9 and the flip count and distortion figures of the report.
#
# Usage: RICCI=/path/to/ricci bash tests/cli/polygons_test.sh [SCRATCH_DIR]
# Needs bash and /usr/bin/python3. The checkuv checks are skipped when ../shared/tools/checkuv.py
# is missing.
set -u

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
# shellcheck source=check_framework.sh
source "$here/check_framework.sh" polygons "${1:-}"
checkuv="$here/../../../shared/tools/checkuv.py"
[[ -f "$checkuv" ]] || echo "note: $checkuv not found: the checkuv checks are skipped"

# Generated meshes: a quad torus (OBJ), a quad sphere (OFF: closed genus 0, automatic cones),
# a bent 3 by 3 grid whose lower-left L is one non-convex octagon (OBJ; its fan from the first
# corner is degenerate) and a quad cylinder (PLY ASCII).
"$PYTHON" - <<'PY' || exit 2
import math

def write_obj(path, V, F):
    with open(path, "w") as f:
        for v in V: f.write("v %.17g %.17g %.17g\n" % v)
        for face in F: f.write("f " + " ".join(str(i + 1) for i in face) + "\n")

def write_off(path, V, F):
    with open(path, "w") as f:
        f.write("OFF\n%d %d 0\n" % (len(V), len(F)))
        for v in V: f.write("%.17g %.17g %.17g\n" % v)
        for face in F: f.write("%d %s\n" % (len(face), " ".join(map(str, face))))

def write_ply(path, V, F):
    with open(path, "w") as f:
        f.write("ply\nformat ascii 1.0\nelement vertex %d\nproperty double x\nproperty double y\n"
                "property double z\nelement face %d\nproperty list uchar int vertex_indices\n"
                "end_header\n" % (len(V), len(F)))
        for v in V: f.write("%.17g %.17g %.17g\n" % v)
        for face in F: f.write("%d %s\n" % (len(face), " ".join(map(str, face))))

n, m = 16, 8
V = [((1 + 0.4 * math.cos(2 * math.pi * j / m)) * math.cos(2 * math.pi * i / n),
      (1 + 0.4 * math.cos(2 * math.pi * j / m)) * math.sin(2 * math.pi * i / n),
      0.4 * math.sin(2 * math.pi * j / m)) for i in range(n) for j in range(m)]
F = [(i * m + j, (i + 1) % n * m + j, (i + 1) % n * m + (j + 1) % m, i * m + (j + 1) % m)
     for i in range(n) for j in range(m)]
write_obj("quad_torus.obj", V, F)

k = 4
keys, V, F = {}, [], []
def vertex(key):
    if key not in keys:
        keys[key] = len(V)
        r = math.sqrt(sum(x * x for x in key))
        V.append(tuple(x / r for x in key))
    return keys[key]
for axis in range(3):
    for sign in (1, -1):
        a, b = (axis + 1) % 3, (axis + 2) % 3
        for s in range(k):
            for t in range(k):
                def key(s, t):
                    p = [0, 0, 0]
                    p[axis] = sign * k
                    p[a if sign > 0 else b] = 2 * s - k
                    p[b if sign > 0 else a] = 2 * t - k
                    return tuple(p)
                F.append((vertex(key(s, t)), vertex(key(s + 1, t)), vertex(key(s + 1, t + 1)),
                          vertex(key(s, t + 1))))
write_off("quad_sphere.off", V, F)

V = [(x, y, 0.1 * (x - 1.5) ** 2) for y in range(4) for x in range(4)]
v = lambda x, y: 4 * y + x
F = [(v(0, 0), v(1, 0), v(2, 0), v(2, 1), v(1, 1), v(1, 2), v(0, 2), v(0, 1))]
F += [(v(x, y), v(x + 1, y), v(x + 1, y + 1), v(x, y + 1))
      for x, y in ((2, 0), (1, 1), (2, 1), (0, 2), (1, 2), (2, 2))]
write_obj("octagon.obj", V, F)

n, m = 12, 5
V = [(math.cos(2 * math.pi * i / n), math.sin(2 * math.pi * i / n), 2.0 * j / m)
     for j in range(m + 1) for i in range(n)]
F = [(j * n + i, j * n + (i + 1) % n, (j + 1) * n + (i + 1) % n, (j + 1) * n + i)
     for j in range(m) for i in range(n)]
write_ply("quad_cylinder.ply", V, F)
PY

# same_faces INPUT OUTPUT.obj: the output has the input's vertices (same order and coordinates)
# and its faces in its order, each with the same corners in the same cyclic order, every corner
# with a vt.
same_faces() {
  "$PYTHON" - "$1" "$2" <<'PY'
import sys

def read(path):
    V, F = [], []
    lines = open(path).read().split("\n")
    if path.endswith(".off"):
        n, f = map(int, lines[1].split()[:2])
        V = [tuple(map(float, l.split()[:3])) for l in lines[2:2 + n]]
        F = [tuple(map(int, l.split()[1:])) for l in lines[2 + n:2 + n + f]]
        return V, F, True
    if path.endswith(".ply"):
        start = lines.index("end_header") + 1
        nv = int([l for l in lines if l.startswith("element vertex")][0].split()[2])
        nf = int([l for l in lines if l.startswith("element face")][0].split()[2])
        V = [tuple(map(float, l.split()[:3])) for l in lines[start:start + nv]]
        F = [tuple(map(int, l.split()[1:])) for l in lines[start + nv:start + nv + nf]]
        return V, F, True
    every_vt = True
    for l in lines:
        p = l.split()
        if not p: continue
        if p[0] == "v": V.append(tuple(map(float, p[1:4])))
        if p[0] == "f":
            F.append(tuple(int(c.split("/")[0]) - 1 for c in p[1:]))
            every_vt &= all(len(c.split("/")) > 1 and c.split("/")[1] != "" for c in p[1:])
    return V, F, every_vt

def same_cycle(a, b):
    return len(a) == len(b) and any(a == b[s:] + b[:s] for s in range(len(b)))

Vi, Fi, _ = read(sys.argv[1])
Vo, Fo, every_vt = read(sys.argv[2])
problems = []
if Vi != Vo: problems.append("vertices differ (%d in, %d out)" % (len(Vi), len(Vo)))
if len(Fi) != len(Fo): problems.append("%d faces in, %d out" % (len(Fi), len(Fo)))
bad = [i for i, (a, b) in enumerate(zip(Fi, Fo)) if not same_cycle(a, b)]
if bad: problems.append("face %d is %s, was %s" % (bad[0], Fo[bad[0]], Fi[bad[0]]))
if not every_vt: problems.append("a corner without vt")
print("; ".join(problems))
sys.exit(1 if problems else 0)
PY
}

# check_uv NAME OUT.obj REPORT.json: checkuv finds no flipped or degenerate face, seams matching
# to 1e-9, and the report's flip count, area distortion (to 1e-9) and largest angle distortion
# (to 1e-6).
check_uv() {
  [[ -f "$checkuv" ]] || return 0
  if ! "$PYTHON" "$checkuv" "$2" >"$1.check.json" 2>"$1.check.err"; then
    fail "$1: checkuv" "$(head -c 300 "$1.check.err")"
    return
  fi
  local why
  why=$("$PYTHON" - "$1.check.json" "$3" <<'PY'
import json, sys
c = json.load(open(sys.argv[1]))
d = json.load(open(sys.argv[2]))["distortion"]
problems = []
if c["flipped"] != 0: problems.append("checkuv counts %d flipped faces" % c["flipped"])
if c["degenerate"] != 0: problems.append("checkuv counts %d degenerate faces" % c["degenerate"])
if c["flipped"] != d["flipped_faces"]:
    problems.append("report %d flipped, checkuv %d" % (d["flipped_faces"], c["flipped"]))
if not c["seam_length_mismatch"] <= 1e-9:
    problems.append("seam mismatch %g" % c["seam_length_mismatch"])
def close(a, b, tol):
    return abs(a - b) <= tol * max(1.0, abs(a), abs(b))
if not close(c["area_distortion_energy"], d["area_distortion_energy"], 1e-9):
    problems.append("area distortion %r, report %r" % (c["area_distortion_energy"], d["area_distortion_energy"]))
# checkuv takes sigma_min from a difference that cancels near 1 (about 1e-8 off for a conformal
# face); the report's ratio does not.
if not close(c["angle_distortion_max"], d["angle_distortion_max"], 1e-6):
    problems.append("angle distortion max %r, report %r" % (c["angle_distortion_max"], d["angle_distortion_max"]))
print("; ".join(problems))
PY
)
  if [[ -z "$why" ]]; then ok; else fail "$1: checkuv" "$why"; fi
}

for mesh in quad_torus.obj quad_sphere.off octagon.obj quad_cylinder.ply; do
  name="${mesh%.*}"
  if "$RICCI" param "$mesh" -o "$name.uv.obj" --texture none --report "$name.json" \
    >"$name.out" 2>"$name.err"; then ok; else
    fail "$name: param" "exit code $?: $(head -c 300 "$name.err")"
    continue
  fi
  if why=$(same_faces "$mesh" "$name.uv.obj"); then ok; else fail "$name: same faces" "$why"; fi
  if grep -q "faces: the input's" "$name.out"; then ok; else
    fail "$name: summary" "no line about the polygons: $(tr '\n' ' ' <"$name.out")"
  fi
  "$PYTHON" -c 'import json,sys; sys.exit(0 if json.load(open(sys.argv[1]))["polygons"] > 0 else 1)' \
    "$name.json" && ok || fail "$name: report" "polygons is not > 0"
  check_uv "$name" "$name.uv.obj" "$name.json"
done

# The octagon's fan from its file's first corner is degenerate: it is written from a corner
# whose fan is sound, the same face.
if [[ -f octagon.uv.obj ]] && ! grep -qE '^f 1/[0-9]+ 2/[0-9]+ 3/' octagon.uv.obj; then
  ok
else
  fail "octagon: start corner" "$(grep -m1 '^f' octagon.uv.obj)"
fi

# ricci batch runs ricci param: its OBJ keeps the polygons too.
mkdir -p batch_in
cp quad_torus.obj octagon.obj batch_in/
if "$RICCI" batch batch_in -o batch_out --jobs 1 >batch.out 2>&1; then ok; else
  fail "batch" "$(tail -c 300 batch.out)"
fi
for name in quad_torus octagon; do
  if why=$(same_faces "batch_in/$name.obj" "batch_out/$name.obj"); then ok; else
    fail "batch $name: same faces" "$why"
  fi
  check_uv "batch_$name" "batch_out/$name.obj" "batch_out/$name.json"
done

finish
