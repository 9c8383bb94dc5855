#!/usr/bin/env bash
# End-to-end tests of the `ricci` program: help and version, `generate` and `info` on every
# built-in mesh, `flow` with every target, scheme and solver, and the refusal of bad input
# (exit code 2, a message naming the file and the element, no output written).
#
# Usage: RICCI=/path/to/ricci bash tests/cli/cli_test.sh [SCRATCH_DIR]
# Needs bash, coreutils, grep and /usr/bin/python3 (for the JSON checks). Prints one line per
# failed check and finally "N passed, M failed"; exits 1 when a check failed. The working folder
# under SCRATCH_DIR is removed when every check passed and kept for inspection otherwise.
set -u

CLI_TEST_DIR="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
# shellcheck source=check_framework.sh
source "$CLI_TEST_DIR/check_framework.sh" cli "${1:-}"

# ricci ARGS...: runs the program; stdout in $WORK/out.txt, stderr in $WORK/err.txt, code in $rc.
rc=0
ricci() {
  "$RICCI" "$@" >"$WORK/out.txt" 2>"$WORK/err.txt"
  rc=$?
}
first_error() { head -n 3 "$WORK/err.txt" | tr '\n' ' '; }

# expect_rc NAME WANT: the last ricci run exited with WANT.
expect_rc() {
  if [[ "$rc" == "$2" ]]; then ok; else fail "$1" "exit code $rc, expected $2; stderr: $(first_error)"; fi
}

# expect_in NAME FILE TEXT...: FILE contains every TEXT (fixed strings).
expect_in() {
  local name="$1" file="$2" text
  shift 2
  for text in "$@"; do
    if grep -qF -- "$text" "$file"; then ok; else
      fail "$name" "'$text' not in $(basename "$file"): $(head -c 300 "$file" | tr '\n' ' ')"
    fi
  done
}
expect_err() { local name="$1"; shift; expect_in "$name" "$WORK/err.txt" "$@"; }
expect_out() { local name="$1"; shift; expect_in "$name" "$WORK/out.txt" "$@"; }

# expect_json NAME FILE PYTHON_EXPR: the expression is true with `d` the parsed JSON of FILE.
expect_json() {
  local reason
  if reason="$("$PYTHON" - "$2" "$3" 2>&1 <<'EOF'
import json, math, sys
try:
    with open(sys.argv[1]) as f:
        d = json.load(f)
except Exception as e:
    print(f"cannot read JSON: {e}")
    sys.exit(1)
if not eval(sys.argv[2], {"d": d, "math": math}):
    print(f"false: {sys.argv[2]}")
    sys.exit(1)
EOF
  )"; then ok; else fail "$1" "$reason"; fi
}

expect_file() { if [[ -f "$2" ]]; then ok; else fail "$1" "$2 was not written"; fi; }
expect_no_file() { if [[ ! -e "$2" ]]; then ok; else fail "$1" "$2 exists but must not"; fi; }
checksum() { if [[ -f "$1" ]]; then sha256sum <"$1"; else echo "missing"; fi; }
expect_same() {  # expect_same NAME FILE CHECKSUM
  local now
  now="$(checksum "$2")"
  if [[ "$now" == "$3" ]]; then ok; elif [[ "$now" == missing ]]; then fail "$1" "$2 was removed"
  else fail "$1" "$2 was modified"; fi
}
# expect_no_temporaries NAME DIR: no temporary files of the atomic writer are left in DIR.
expect_no_temporaries() {
  local left
  left="$(find "$2" -maxdepth 1 -name '.*.tmp*' | head -n 3 | tr '\n' ' ')"
  if [[ -z "$left" ]]; then ok; else fail "$1" "temporary files left: $left"; fi
}

# --- help, version, parse errors ---------------------------------------------------------------
ricci --version
expect_rc "--version" 0
expect_out "--version" "ricci 0.1.0"

ricci --help
expect_rc "--help" 0
expect_out "--help" "info" "flow" "generate" "--version" "Exit codes"

ricci info --help
expect_rc "info --help" 0
expect_out "info --help" "MESH" "--json"

ricci flow --help
expect_rc "flow --help" 0
expect_out "flow --help" "--scheme" "=vertex-scaling" "thurston" "tangential" "inversive-distance" "vertex-scaling" \
  "virtual-radius" "--init" "=fit" "--target" "=natural" "disk-length" "uniform" "--boundary" \
  "free (the euclidean default)" "geodesic (the hyperbolic default)" "--geometry" "=euclidean" \
  "hyperbolic" "--cones" "--solver" "=newton" "--tol" "1e-10" "--max-iterations" "--step" \
  "-o,--output" "--json" "--progress"

ricci generate --help
expect_rc "generate --help" 0
expect_out "generate --help" "KIND" "tetrahedron" "icosphere" "disk" "torus" "surface" \
  "--resolution" "--genus" "=2" "--holes" "-o,--output"

ricci
expect_rc "no subcommand" 2
ricci frobnicate
expect_rc "unknown subcommand" 2
ricci --frobnicate
expect_rc "unknown global option" 2
ricci info --frobnicate x.obj
expect_rc "unknown info option" 2
ricci flow
expect_rc "flow without MESH" 2
ricci generate torus
expect_rc "generate without -o" 2
ricci generate blob -o blob.obj
expect_rc "generate unknown kind" 2
expect_err "generate unknown kind" "blob"
expect_no_file "generate unknown kind writes nothing" blob.obj

# --- generate + info on every built-in mesh ----------------------------------------------------
mkdir -p meshes
# gen NAME ARGS...: writes meshes/NAME.obj.
gen() {
  local name="$1"
  shift
  ricci generate "$@" -o "meshes/$name.obj"
  expect_rc "generate $name" 0
  expect_file "generate $name" "meshes/$name.obj"
}
gen tetrahedron tetrahedron
gen icosphere icosphere
gen disk disk
gen torus torus
gen genus2 surface --genus 2
gen genus1_holes2 surface --genus 1 --holes 2
gen small_torus torus --resolution 6
gen small_icosphere icosphere --resolution 1
gen small_disk disk --resolution 4
expect_no_temporaries "generate leaves no temporaries" meshes

# info_json NAME EXPR: `info --json` on meshes/NAME.obj succeeds and satisfies EXPR.
info_json() {
  ricci info "meshes/$1.obj" --json
  expect_rc "info $1" 0
  cp "$WORK/out.txt" "info_$1.json"
  expect_json "info $1 is consistent" "info_$1.json" \
    'd["valid"] is True and d["defects"] == [] and d["components"] == 1 and d["vertices"] - d["edges"] + d["faces"] == d["euler_characteristic"] == 2 - 2 * d["genus"] - d["boundary_loops"]'
  expect_json "info $1" "info_$1.json" "$2"
}
info_json tetrahedron 'd["vertices"] == 4 and d["edges"] == 6 and d["faces"] == 4 and d["genus"] == 0 and d["boundary_loops"] == 0 and d["euler_characteristic"] == 2'
# Icosphere of 3 subdivisions: 10 * 4^3 + 2 vertices, 20 * 4^3 faces.
info_json icosphere 'd["vertices"] == 642 and d["edges"] == 1920 and d["faces"] == 1280 and d["genus"] == 0 and d["boundary_loops"] == 0'
# Disk of 16 rings: 1 + 3 * 16 * 17 vertices, 6 * 16^2 faces.
info_json disk 'd["vertices"] == 817 and d["faces"] == 1536 and d["genus"] == 0 and d["boundary_loops"] == 1 and d["euler_characteristic"] == 1'
# Torus of 64 x 32 quads, each split in two.
info_json torus 'd["vertices"] == 2048 and d["edges"] == 6144 and d["faces"] == 4096 and d["genus"] == 1 and d["boundary_loops"] == 0 and d["euler_characteristic"] == 0'
info_json genus2 'd["genus"] == 2 and d["boundary_loops"] == 0 and d["euler_characteristic"] == -2'
info_json genus1_holes2 'd["genus"] == 1 and d["boundary_loops"] == 2 and d["euler_characteristic"] == -2'
info_json small_torus 'd["vertices"] == 72 and d["faces"] == 144 and d["genus"] == 1'
info_json small_icosphere 'd["vertices"] == 42 and d["faces"] == 80 and d["genus"] == 0'
info_json small_disk 'd["vertices"] == 61 and d["faces"] == 96 and d["boundary_loops"] == 1'

ricci info meshes/torus.obj
expect_rc "info text" 0
expect_out "info text" "meshes/torus.obj" "vertices" "2048" "Euler characteristic" "genus" "defects" "none"

# --- flow ------------------------------------------------------------------------------------
# flow_ok NAME MESH ARGS...: `flow --json` converges to the default tolerance 1e-10.
flow_ok() {
  local name="$1"
  shift
  ricci flow "$@" --json
  expect_rc "flow $name" 0
  cp "$WORK/out.txt" "flow.json"
  expect_json "flow $name converges" flow.json \
    'd["converged"] is True and d["max_error"] <= 1e-10 and all(c["converged"] for c in d["components"])'
}

flow_ok "torus flat" meshes/torus.obj
expect_json "flow torus flat summary" flow.json \
  'd["scheme"] == "vertex-scaling" and d["solver"] == "newton" and d["vertices"] == 2048 and d["edges"] == 6144 and d["faces"] == 4096 and d["tolerance"] == 1e-10 and d["components"][0]["genus"] == 1'

for target in free disk disk-length; do
  flow_ok "disk --target $target" meshes/disk.obj --target "$target"
done
flow_ok "disk --boundary disk-length" meshes/small_disk.obj --boundary disk-length

flow_ok "genus 2 uniform" meshes/genus2.obj --target uniform
flow_ok "genus 1 with 2 holes, free boundary" meshes/genus1_holes2.obj --target free

# Four cones of curvature pi on a sphere satisfy Gauss-Bonnet (4 pi = 2 pi chi).
flow_ok "icosphere --cones list" meshes/icosphere.obj --cones '0:pi,3:pi,5:pi,9:pi'
expect_json "icosphere --cones list" flow.json '"4 cones" in d["target"]'
printf '# vertex curvature\n0 pi\n3 3.141592653589793\n5 pi\n9 pi  # last\n' >cones.txt
flow_ok "icosphere --cones file" meshes/icosphere.obj --cones cones.txt
# A torus: a cone pair of opposite curvature.
flow_ok "torus --cones pair" meshes/torus.obj --cones '0:pi/2,1000:-pi/2'

# --target FILE: the uniform curvature 2 pi chi / n written out per vertex.
"$PYTHON" -c '
import math, sys
n = 42
with open(sys.argv[1], "w") as f:
    f.write("# 4 pi / 42 at every vertex\n")
    f.writelines(f"{4 * math.pi / n!r}\n" for _ in range(n))
' target_values.txt
flow_ok "--target FILE" meshes/small_icosphere.obj --target target_values.txt -o target_result.json
expect_json "--target FILE reached" target_result.json \
  'all(abs(k - 4 * math.pi / 42) < 1e-9 for k in d["vertex_data"]["curvature"]) and all(abs(k - 4 * math.pi / 42) < 1e-15 for k in d["vertex_data"]["target_curvature"])'

flow_ok "gradient solver" meshes/small_icosphere.obj --solver gradient --target uniform
expect_json "gradient solver" flow.json 'd["solver"] == "gradient"'
flow_ok "gradient solver with cones" meshes/small_icosphere.obj --solver gradient --cones '0:pi,3:pi,5:pi,9:pi'

for scheme in thurston tangential inversive-distance vertex-scaling virtual-radius; do
  flow_ok "--scheme $scheme" meshes/small_torus.obj --scheme "$scheme"
  expect_json "--scheme $scheme" flow.json "d[\"scheme\"] == \"$scheme\""
done
flow_ok "--init unit" meshes/small_torus.obj --init unit

# Intrinsic Delaunay flips: a cone of angle 4 pi at a degree-5 vertex breaks triangles without
# flips (exit 3, saying so) and converges with them (the default for vertex scaling).
strong_cones='0:-2pi,5:1.5pi,11:1.5pi,20:1.5pi,30:1.5pi'
ricci flow meshes/icosphere.obj --scheme vertex-scaling --flips off --cones "$strong_cones"
expect_rc "--flips off on strong cones" 3
expect_out "--flips off on strong cones" "triangle inequality" "try: --flips delaunay"
flow_ok "--flips auto on strong cones" meshes/icosphere.obj --scheme vertex-scaling \
  --cones "$strong_cones" -o flips.json
expect_json "--flips auto flipped" flow.json \
  'd["flips"] == "auto" and d["flipped_edges"] > 0 and sum(r["flips"] for r in d["components"][0]["history"]) == d["flipped_edges"]'
expect_json "--flips -o has the intrinsic triangles" flips.json \
  'len(d["vertex_data"]["triangles"]) == d["faces"] and len(d["vertex_data"]["edges"]) == d["edges"]'
ricci flow meshes/icosphere.obj --scheme thurston --flips delaunay
expect_rc "--flips delaunay with thurston" 2
expect_err "--flips delaunay with thurston" "vertex-scaling"
ricci flow meshes/icosphere.obj --flips sometimes
expect_rc "--flips unknown" 2
ricci param meshes/icosphere.obj -o flipped_param.obj --scheme vertex-scaling \
  --cones "$strong_cones" --json
expect_rc "param with flips" 0
expect_out "param with flips" '"flipped_edges"'
expect_json "param with flips: input vertices, intrinsic faces" "$WORK/out.txt" \
  'd["flow"]["flipped_edges"] > 0 and d["distortion"]["flipped_faces"] == 0'
expect_json "param: the angle polish moves the interior and lowers the face-mean distortion" \
  "$WORK/out.txt" \
  'd["polish"]["enabled"] and d["polish"]["moved_vertices"] > 0 and d["polish"]["angle_distortion_face_mean_after"] < d["polish"]["angle_distortion_face_mean_before"]'
# --polish none: the discrete conformal map itself (what the refinement below extends).
ricci param meshes/icosphere.obj -o exact_param.obj --scheme vertex-scaling \
  --cones "$strong_cones" --polish none --json
expect_rc "param --polish none" 0
expect_json "param --polish none moves nothing" "$WORK/out.txt" \
  'not d["polish"]["enabled"] and d["polish"]["moved_vertices"] == 0 and d["timings"]["polish"] == 0'
ricci param meshes/icosphere.obj -o exact_param.obj --polish sometimes
expect_rc "param --polish unknown" 2
# --faces refinement: the common refinement with homogeneous vt, its linear twin, the vertex map
# and the interpolation matrix; the input's vertices first, at the uv of the output without the
# angle polish (the refinement is the exact map: it never polishes).
mkdir -p refined
ricci param meshes/icosphere.obj -o refined/sphere.obj --scheme vertex-scaling \
  --cones "$strong_cones" --faces refinement --report refined/sphere.json
expect_rc "param --faces refinement" 0
for f in sphere.obj sphere.linear.obj sphere.vertex_map.txt sphere.spmat; do
  expect_file "param --faces refinement writes $f" "refined/$f"
done
expect_out "param --faces refinement" "refinement" "sphere.spmat"
expect_json "param --faces refinement report" refined/sphere.json \
  'd["refinement"]["ptolemy_flips"] > 0 and d["refinement"]["vertices"] > d["refinement"]["input_vertices"] and d["refinement"]["max_intrinsic_length_error"] < 1e-9 and d["refinement"]["inverted_triangles"] == 0 and d["refinement"]["files"]["linear"].endswith("sphere.linear.obj")'
if "$PYTHON" - refined/sphere.obj refined/sphere.linear.obj refined/sphere.vertex_map.txt \
    refined/sphere.spmat exact_param.obj <<'EOF'
import sys
def read(path):
    v, vt, f = [], [], []
    for line in open(path):
        w = line.split()
        if not w: continue
        if w[0] == "v": v.append([float(x) for x in w[1:4]])
        elif w[0] == "vt": vt.append([float(x) for x in w[1:]])
        elif w[0] == "f": f.append([tuple(int(i) - 1 for i in c.split("/")) for c in w[1:]])
    return v, vt, f
v, vt, f = read(sys.argv[1])
lv, lvt, lf = read(sys.argv[2])
dv, dvt, df = read(sys.argv[5])
assert v == lv and len(f) == len(lf) and all(len(t) == 3 for t in vt)
# Homogeneous corners divided by w give the linear file's uv.
for face, lface in zip(f, lf):
    for (a, t), (b, s) in zip(face, lface):
        assert a == b and vt[t][2] > 0
        assert abs(vt[t][0] / vt[t][2] - lvt[s][0]) < 1e-12 and abs(vt[t][1] / vt[t][2] - lvt[s][1]) < 1e-12
# The vertex map: input vertex i is refinement vertex i, at the same place, with the texture
# coordinates of the output without polish at its corners.
pairs = [tuple(int(x) - 1 for x in line.split()) for line in open(sys.argv[3]) if not line.startswith("#")]
assert len(pairs) == len(dv) and all(v[r] == dv[i] for i, r in pairs)
default_uv = {(a, tuple(dvt[t])) for face in df for a, t in face}
refined_uv = {(a, tuple(lvt[t])) for face in lf for a, t in face if a < len(dv)}
assert refined_uv == default_uv
# The interpolation matrix: rows sum to 1 and reproduce the positions.
rows = {}
entries = [line.split() for line in open(sys.argv[4])]
shape = entries.pop()
assert int(shape[0]) == len(v) and int(shape[1]) == len(dv) and float(shape[2]) == 0
for r, c, w in entries:
    rows.setdefault(int(r) - 1, []).append((int(c) - 1, float(w)))
assert len(rows) == len(v)
for r, row in rows.items():
    assert abs(sum(w for _, w in row) - 1) < 1e-14
    p = [sum(w * dv[c][k] for c, w in row) for k in range(3)]
    assert max(abs(p[k] - v[r][k]) for k in range(3)) < 1e-12
EOF
then ok; else fail "param --faces refinement files" "the refinement files disagree"; fi
ricci param meshes/icosphere.obj -o refined/thurston.obj --scheme thurston --cones "$strong_cones" \
  --faces refinement
expect_rc "param --faces refinement with thurston" 2
expect_err "param --faces refinement with thurston" "vertex-scaling"
expect_no_file "param --faces refinement with thurston writes nothing" refined/thurston.obj
ricci param meshes/icosphere.obj -o refined/x.obj --faces exact
expect_rc "param --faces unknown" 2
ricci render --help
if [[ "$rc" == 0 ]]; then
  ricci render refined/sphere.obj -o refined/sphere.png --width 96 --height 96
  expect_rc "render a homogeneous refinement" 0
  expect_file "render a homogeneous refinement" refined/sphere.png
fi

ricci flow meshes/small_torus.obj --progress
expect_rc "--progress" 0
expect_err "--progress" "iteration    0" "max |K-bar - K|"
expect_out "flow text" "converged" "component 0"

# -o writes the full result atomically.
mkdir -p results
ricci flow meshes/small_torus.obj -o results/torus.json
expect_rc "flow -o" 0
expect_file "flow -o" results/torus.json
expect_out "flow -o" "wrote results/torus.json"
expect_json "flow -o vertex_data" results/torus.json \
  'd["converged"] is True and all(len(d["vertex_data"][k]) == d["vertices"] == 72 for k in ("u", "curvature", "target_curvature", "file_index")) and len(d["vertex_data"]["edges"]) == len(d["vertex_data"]["lengths"]) == d["edges"] == 216'
expect_json "flow -o values" results/torus.json \
  'all(abs(k) < 1e-9 for k in d["vertex_data"]["curvature"]) and all(l > 0 for l in d["vertex_data"]["lengths"]) and all(len(e) == 2 and 0 <= min(e) and max(e) < 72 for e in d["vertex_data"]["edges"])'
expect_no_temporaries "flow -o leaves no temporaries" results

# Not converged: exit 3.
ricci flow meshes/torus.obj --solver gradient --max-iterations 1 --json
expect_rc "not converged" 3
cp "$WORK/out.txt" not_converged.json
expect_json "not converged" not_converged.json 'd["converged"] is False and d["max_error"] > 1e-10'

# A numerical breakdown (the library's SolverError, injected with param's hidden --fault) is a
# computation that did not converge, not a bug: exit 3, saying so, and no output.
RICCI_FAULT_INJECTION=1 ricci param meshes/torus.obj -o breakdown.obj --fault solver
expect_rc "numerical breakdown" 3
expect_err "numerical breakdown" "error: numerical breakdown: --fault solver"
expect_no_file "numerical breakdown" breakdown.obj

# --- bad meshes --------------------------------------------------------------------------------
mkdir -p bad
: >bad/empty.obj
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >bad/triangle.xyz
# A tetrahedron with the header of each defect; the defective element is on the line noted.
printf 'v 0 0 0\nv 1 0 0\nv 0 nan 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' >bad/nan.obj
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 1000000000\nf 1 4 3\nf 2 3 4\n' >bad/index.obj
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 4 4\nf 1 4 3\nf 2 3 4\n' >bad/repeated.obj
# Three triangles on the edge (1, 2).
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n' >bad/nonmanifold_edge.obj
# A bowtie: two triangles that share only vertex 1.
printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv -1 0 0\nv -1 -1 0\nf 1 2 3\nf 1 4 5\n' >bad/bowtie.obj
# Both triangles traverse the edge (2, 3) from 2 to 3.
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 3 4\n' >bad/orientation.obj
# Three collinear vertices.
printf 'v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 4\nf 1 3 2\n' >bad/zero_area.obj
"$PYTHON" - <<'EOF'
import math, struct
# A Moebius strip: a band of 10 quads whose last quad joins the first with a half twist.
n = 10
with open("bad/moebius.obj", "w") as f:
    for i in range(n):
        angle = 2 * math.pi * i / n
        for s in (-0.3, 0.3):
            r = 1 + s * math.cos(angle / 2)
            f.write(f"v {r * math.cos(angle):.9f} {r * math.sin(angle):.9f} {s * math.sin(angle / 2):.9f}\n")
    for i in range(n):
        top, bottom = 1 + 2 * i, 2 + 2 * i
        next_top, next_bottom = (top + 2, bottom + 2) if i < n - 1 else (2, 1)
        f.write(f"f {top} {bottom} {next_bottom}\nf {top} {next_bottom} {next_top}\n")
# A binary little-endian PLY tetrahedron, whole and cut inside its last face.
header = ("ply\nformat binary_little_endian 1.0\nelement vertex 4\n"
          "property float x\nproperty float y\nproperty float z\n"
          "element face 4\nproperty list uchar int vertex_indices\nend_header\n").encode()
vertices = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
faces = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
body = b"".join(struct.pack("<3f", *v) for v in vertices)
body += b"".join(struct.pack("<B3i", 3, *f) for f in faces)
with open("bad/tetrahedron.ply", "wb") as f:
    f.write(header + body)
with open("bad/cut.ply", "wb") as f:
    f.write(header + body[:-7])
EOF

ricci info bad/tetrahedron.ply --json
expect_rc "binary PLY reads" 0
cp "$WORK/out.txt" ply.json
expect_json "binary PLY reads" ply.json 'd["vertices"] == 4 and d["faces"] == 4 and d["genus"] == 0 and d["valid"] is True'

# bad_mesh NAME FILE TEXT...: flow refuses FILE with exit 2, a message naming the file and every
# TEXT, and writes no -o file.
bad_mesh() {
  local name="$1" file="$2"
  shift 2
  rm -f bad_out.json
  ricci flow "$file" -o bad_out.json
  expect_rc "$name" 2
  expect_err "$name" "$(basename "$file")" "$@"
  expect_no_file "$name writes no output" bad_out.json
}
bad_mesh "missing file" bad/missing.obj "no such file"
bad_mesh "0-byte file" bad/empty.obj "empty"
bad_mesh "unknown extension" bad/triangle.xyz ".xyz"
bad_mesh "NaN coordinate" bad/nan.obj "line 3" "vertex 2" "non-finite"
bad_mesh "face index out of range" bad/index.obj "line 6" "1000000000"
bad_mesh "Moebius strip" bad/moebius.obj "line" "non-orientable"
bad_mesh "truncated binary PLY" bad/cut.ply "byte" "truncated"
expect_no_temporaries "bad input leaves no temporaries" .

# strict_mesh NAME FILE TEXT...: a defect repair fixes: flow --strict refuses FILE like bad_mesh,
# naming the fix; --repair=never names its own; by default (--repair=auto) flow repairs it with
# warnings and goes on.
strict_mesh() {
  local name="$1" file="$2"
  shift 2
  rm -f bad_out.json
  ricci flow "$file" --strict -o bad_out.json
  expect_rc "$name --strict" 2
  expect_err "$name --strict" "$(basename "$file")" "$@" "try: drop --strict"
  expect_no_file "$name --strict writes no output" bad_out.json
  ricci flow "$file" --repair=never -o bad_out.json
  expect_rc "$name --repair=never" 2
  expect_err "$name --repair=never" "try: --repair=auto"
  ricci flow "$file" -o bad_out.json
  expect_rc "$name repaired by default" 0
  expect_err "$name repaired by default" "warning: $file: repairing: the mesh has defects" \
    "warning: repair: $file: " "; the mesh was repaired"
  expect_json "$name repaired by default: the report" bad_out.json \
    'd["repair"]["mode"] == "auto" and d["repair"]["changed"] is True'
}
strict_mesh "face repeats a vertex" bad/repeated.obj "line 6" "face 1" "more than once"
strict_mesh "non-manifold edge" bad/nonmanifold_edge.obj "line 6" "non-manifold edge" "(0, 1)"
strict_mesh "non-manifold vertex" bad/bowtie.obj "non-manifold vertex 0"
strict_mesh "inconsistent orientation" bad/orientation.obj "line 6" "inconsistent orientation" "faces 1 and 0"
strict_mesh "zero-area face" bad/zero_area.obj "line 6" "face 1" "zero area"
ricci flow bad/bowtie.obj --strict --repair
expect_rc "--strict with --repair" 2
expect_err "--strict with --repair" "--repair excludes --strict"
ricci flow bad/bowtie.obj --repair=sometimes
expect_rc "--repair=sometimes" 2
expect_err "--repair=sometimes" "expected --repair, --repair=always, --repair=auto or --repair=never"

# info lists the defects of a defective mesh and exits 2, and says what repair would do.
ricci info bad/nonmanifold_edge.obj
expect_rc "info on a defective mesh" 2
expect_out "info on a defective mesh" "defects:" "non-manifold-edge: 1" "non-manifold edge (0, 1) is shared by 3 faces" \
  "repair:              the other commands repair this mesh" "split 1 non-manifold edges"
ricci info bad/nonmanifold_edge.obj --json
cp "$WORK/out.txt" would_repair.json
expect_json "info --json on a defective mesh: auto_repair" would_repair.json \
  'd["valid"] is False and d["auto_repair"]["would_repair"] is True and d["auto_repair"]["valid_after"] is True and d["auto_repair"]["repair"]["non_manifold_edges_split"]["count"] == 1'
ricci info bad/nonmanifold_edge.obj --strict
expect_rc "info --strict on a defective mesh" 2
if grep -q "the other commands" "$WORK/out.txt"; then fail "info --strict" "shows the repair"; else ok; fi
ricci info bad/moebius.obj --json
expect_rc "info --json on a Moebius strip" 2
cp "$WORK/out.txt" moebius.json
expect_json "info --json on a Moebius strip" moebius.json \
  'd["valid"] is False and d["defect_counts"].get("non-orientable") == 1 and any(x["kind"] == "non-orientable" for x in d["defects"]) and d["auto_repair"]["valid_after"] is False'
ricci info bad/orientation.obj --json
expect_rc "info --json on inconsistent orientation" 2
cp "$WORK/out.txt" orientation.json
expect_json "info --json on inconsistent orientation" orientation.json \
  'd["valid"] is False and [x["kind"] for x in d["defects"]] == ["inconsistent-orientation"]'

# --- --repair ------------------------------------------------------------------------------------
for cmd in info flow param sphere spline; do
  ricci "$cmd" --help
  expect_out "$cmd --help shows --repair" "--repair [=MODE]" "--strict" "--largest-component"
done

# repaired NAME FILE EXPR TEXT...: `info --repair --json` on FILE exits 0 with a valid mesh, the
# "repair" object satisfies EXPR (r is d["repair"]) and stderr names FILE and every TEXT.
repaired() {
  local name="$1" file="$2" expr="$3"
  shift 3
  ricci info --repair --json "$file"
  expect_rc "info --repair $name" 0
  cp "$WORK/out.txt" repaired.json
  expect_json "info --repair $name" repaired.json "d[\"valid\"] is True and (lambda r: $expr)(d[\"repair\"])"
  expect_err "info --repair $name" "repair: $file: " "$@"
}
repaired "face repeats a vertex" bad/repeated.obj \
  'r["repeated_vertex_faces_removed"] == {"count": 1, "examples": [1]} and r["output_faces"] == 3' \
  "removed 1 faces that use a vertex twice"
repaired "non-manifold edge" bad/nonmanifold_edge.obj \
  'r["non_manifold_edges_split"] == {"count": 1, "examples": [[0, 1]]} and r["vertex_copies_added"] == 2' \
  "split 1 non-manifold edges"
repaired "non-manifold vertex" bad/bowtie.obj \
  'r["non_manifold_vertices_split"] == {"count": 1, "examples": [0]} and r["output_vertices"] == 6' \
  "split 1 non-manifold vertices"
repaired "inconsistent orientation" bad/orientation.obj \
  'r["faces_flipped"] == {"count": 1, "examples": [1]} and r["changed"] is True' "reversed 1 faces"
repaired "zero-area face" bad/zero_area.obj \
  'r["slivers_removed"] == {"count": 1, "examples": [1]} and r["boundary_slivers_removed"] == 1 and r["mode"] == "always"' \
  "removed 1 zero-area faces" "1 on the boundary"
ricci info --repair meshes/small_torus.obj --json
expect_rc "info --repair on a clean mesh" 0
expect_err "info --repair on a clean mesh" "repair: meshes/small_torus.obj: nothing to repair"
cp "$WORK/out.txt" clean.json
expect_json "info --repair on a clean mesh" clean.json 'd["repair"]["changed"] is False and d["vertices"] == 72'

# flow --repair on the non-manifold edge: a flat square and a detached fin, both already flat.
ricci flow --repair bad/nonmanifold_edge.obj --json -o repaired_flow.json
expect_rc "flow --repair" 0
expect_json "flow --repair" repaired_flow.json \
  'd["converged"] is True and d["repair"]["non_manifold_edges_split"]["count"] == 1 and len(d["components"]) == 2 and d["vertex_data"]["file_index"] == [0, 1, 2, 3, 4, 0, 1]'

# What repair cannot fix: exit 2, the changes still on stderr, the message saying why.
bad_repair() {  # bad_repair NAME FILE TEXT...
  local name="$1" file="$2"
  shift 2
  rm -f bad_out.json
  ricci flow --repair "$file" -o bad_out.json
  expect_rc "flow --repair $name" 2
  expect_err "flow --repair $name" "repair: $file:" "$(basename "$file")" "after repair" "$@"
  expect_no_file "flow --repair $name writes no output" bad_out.json
}
bad_repair "Moebius strip" bad/moebius.obj "not repaired: 1 non-orientable components" \
  "repair cannot orient a non-orientable surface"
bad_repair "NaN coordinate" bad/nan.obj "line 3" "repair does not change coordinates"
ricci flow --repair bad/index.obj
expect_rc "flow --repair, index out of range" 2
expect_err "flow --repair, index out of range" "line 6" "1000000000"

# A triangle soup (every face with its own three vertices) of the small disk: read as it is with
# a warning, welded back into the disk by --repair, then parameterized.
"$PYTHON" - meshes/small_disk.obj soup.obj <<'EOF'
import sys
v, f = [], []
for line in open(sys.argv[1]):
    w = line.split()
    if w and w[0] == "v": v.append(line)
    elif w and w[0] == "f": f.append([int(x) for x in w[1:4]])
with open(sys.argv[2], "w") as out:
    for face in f:
        out.writelines(v[i - 1] for i in face)
    out.writelines(f"f {3 * i + 1} {3 * i + 2} {3 * i + 3}\n" for i in range(len(f)))
EOF
ricci info soup.obj
expect_rc "info on a triangle soup" 0
expect_err "info on a triangle soup" "soup.obj: 227 vertices repeat the position of another vertex" "repair welds them"
mkdir -p param
ricci param --repair soup.obj --cones none -o param/soup_uv.obj --report param/soup.json
expect_rc "param --repair on a triangle soup" 0
expect_err "param --repair on a triangle soup" "repair: soup.obj: welded 227 vertices"
expect_json "param --repair report" param/soup.json \
  'd["converged"] and d["repair"]["welded_vertices"]["count"] == 227 and d["repair"]["output_vertices"] == 61 and d["repair"]["input_faces"] == 96'
ricci render --help
if [[ "$rc" == 0 ]]; then
  ricci render --repair param/soup_uv.obj -o soup.png --width 64 --height 64
  expect_rc "render --repair" 0
  expect_err "render --repair" "repair: param/soup_uv.obj: nothing to repair"
  expect_file "render --repair" soup.png
fi

# The non-manifold meshes of shared/meshes, when present.
shared="${RICCI_SHARED_MESHES:-$CLI_TEST_DIR/../../../shared/meshes}"
if [[ -f "$shared/teapot.obj" && -f "$shared/triple_vierbein.obj" ]]; then
  ricci info --repair --json "$shared/teapot.obj"
  expect_rc "info --repair teapot" 0
  cp "$WORK/out.txt" teapot.json
  expect_json "info --repair teapot" teapot.json \
    'd["valid"] and d["repair"]["welded_vertices"]["count"] == 403 and d["components"] == 4 and d["euler_characteristic"] == 2'
  ricci flow --repair "$shared/teapot.obj" --json
  expect_rc "flow --repair teapot" 0
  # Four components, one atlas: every component parameterized, the charts packed apart.
  teapot_pictures=()
  ricci render --help
  [[ "$rc" == 0 ]] && teapot_pictures=(--pictures param/teapot_pics)
  ricci param --repair --scheme vertex-scaling "$shared/teapot.obj" -o param/teapot_uv.obj \
    --report param/teapot.json "${teapot_pictures[@]}"
  expect_rc "param --repair teapot: several components" 0
  expect_out "param --repair teapot: several components" "4 components: 4 flow" \
    "overlapping face pairs 0" "component 3 ("
  expect_json "param --repair teapot report" param/teapot.json \
    'd["converged"] and len(d["components"]) == 4 and all(c["method"] == "flow" and c["parameterized"] for c in d["components"]) and d["packing"]["overlapping_face_pairs"] == 0 and d["packing"]["coverage"] > 0.5 and d["distortion"]["flipped_faces"] == 0'
  # Texture coordinates inside the square, half a gutter from its edges.
  if "$PYTHON" - param/teapot_uv.obj <<'EOF'
import sys
vt = [tuple(map(float, l.split()[1:3])) for l in open(sys.argv[1]) if l.startswith("vt ")]
sys.exit(0 if vt and all(0.001 - 1e-9 <= c <= 0.999 + 1e-9 for t in vt for c in t) else 1)
EOF
  then ok; else fail "param --repair teapot: uv" "texture coordinates outside [0.001, 0.999]"; fi
  if (( ${#teapot_pictures[@]} )); then
    ricci render param/teapot_uv.obj -o param/teapot.png --width 96 --height 96
    expect_rc "render a packed atlas" 0
    expect_file "render a packed atlas" param/teapot.png
    expect_file "param --pictures of several components" param/teapot_pics/uv.png
  fi
  ricci param --repair --scheme vertex-scaling --faces refinement "$shared/teapot.obj" \
    -o param/teapot_refined.obj
  expect_rc "param --faces refinement on several components" 2
  expect_err "param --faces refinement on several components" "4 connected components"
  expect_no_file "param --faces refinement on several components" param/teapot_refined.obj
  checkuv="$shared/../tools/checkuv.py"
  if [[ -f "$checkuv" ]]; then
    "$PYTHON" "$checkuv" param/teapot_uv.obj >param/teapot_check.json
    expect_json "checkuv on the teapot atlas" param/teapot_check.json \
      'd["faces"] == 6320 and d["flipped"] == 0 and d["degenerate"] == 0 and d["seam_length_mismatch"] < 1e-9'
  fi
  ricci param --largest-component "$shared/triple_vierbein.obj" -o param/vierbein_uv.obj --report param/vierbein.json
  expect_rc "param --largest-component triple_vierbein" 0
  expect_json "param --largest-component triple_vierbein" param/vierbein.json \
    'd["converged"] and d["repair"]["non_manifold_edges_split"]["count"] == 20 and d["repair"]["smaller_components_removed"]["count"] == 1'
else
  echo "note: $shared not found: --repair on the shared meshes not checked"
fi

# --- several components: one failing -----------------------------------------------------------
# A saddle (eight faces around vertex 0, 787 degrees of angle) beside a triangle; an inadmissible
# cone on the saddle makes its pipeline fail: charts with free boundary (fold-free, seams their
# 3D length) fill its part of the atlas, the file is written and ricci exits 3 naming the
# component, since the cone asked for was not made.
"$PYTHON" - <<'EOF'
import math
with open("saddle_and_triangle.obj", "w") as out:
    out.write("v 0 0 0\n")
    for i in range(8):
        out.write(f"v {math.cos(math.pi * i / 4)} {math.sin(math.pi * i / 4)} {1 if i % 2 else -1}\n")
    out.write("v 3 0 0\nv 4 0 0\nv 3 1 0\n")
    for i in range(8):
        out.write(f"f 1 {2 + i} {2 + (i + 1) % 8}\n")
    out.write("f 10 11 12\n")
EOF
ricci param saddle_and_triangle.obj --cones 0:7 -o param/saddle_uv.obj --report param/saddle.json
expect_rc "param: a component fails" 3
expect_err "param: a component fails" "1 of 2 components failed" "component 0 (8 faces"
expect_out "param: a component fails" "component 0 (8 faces" "charts" "component 1 (1 faces"
expect_file "param: a component fails: the atlas is still written" param/saddle_uv.obj
expect_json "param: a component fails: report" param/saddle.json \
  'not d["converged"] and [c["method"] for c in d["components"]] == ["charts", "unfolded"] and d["routes"][0]["method"] == "charts" and d["packing"]["overlapping_face_pairs"] == 0'

# --- bad targets and options -------------------------------------------------------------------
# bad_flow NAME TEXT... -- ARGS...: flow ARGS -o bad_out.json exits 2 naming every TEXT, no output.
bad_flow() {
  local name="$1"
  shift
  local texts=()
  while [[ "$1" != "--" ]]; do texts+=("$1"); shift; done
  shift
  rm -f bad_out.json
  ricci flow "$@" -o bad_out.json
  expect_rc "$name" 2
  expect_err "$name" "${texts[@]}"
  expect_no_file "$name writes no output" bad_out.json
}
ico=meshes/icosphere.obj
# The natural default target exists on every topology: uniform on a closed sphere.
ricci flow "$ico" --json
expect_rc "flow sphere with the natural target" 0
cp "$WORK/out.txt" natural.json
expect_json "natural target on a sphere is uniform" natural.json \
  'd["converged"] is True and "uniform" in d["target"]'
bad_flow "flat sphere without cones" "Gauss-Bonnet" "try: --target natural, or --target uniform" \
  -- "$ico" --target flat
bad_flow "cone breaking Gauss-Bonnet" "Gauss-Bonnet" "2 pi chi" "try: drop --cones" -- "$ico" --cones '0:pi'
# With --target flat no single option helps (natural keeps the cones, uniform refuses them).
bad_flow "flat cones breaking Gauss-Bonnet" "Gauss-Bonnet" -- "$ico" --target flat --cones '0:pi'
if grep -q "try:" "$WORK/err.txt"; then fail "flat cones breaking Gauss-Bonnet" "names a fix"; else ok; fi
# -4 pi at a valence-5 vertex, balanced by eight cones of pi: Gauss-Bonnet holds, Thurston's
# single-vertex bound fails (vertex scaling with flips, the default, has no such bound), and so
# does the tangential scheme's (-3 pi), so that only vertex scaling is named.
bad_flow "cone breaking the vertex bound" "vertex 0" "bound" "try: --scheme vertex-scaling" -- \
  "$ico" --scheme thurston --cones '0:-4pi,1:pi,2:pi,3:pi,4:pi,5:pi,6:pi,7:pi,8:pi'
if grep -q "tangential" "$WORK/err.txt"; then fail "cone breaking the vertex bound" "names tangential"; else ok; fi
# -2 pi is within the tangential bound: both schemes are named.
bad_flow "cone breaking Thurston's vertex bound only" "vertex 0" "bound" \
  "try: --scheme vertex-scaling, or --scheme tangential" -- \
  "$ico" --scheme thurston --cones '0:-2pi,5:1.5pi,11:1.5pi,20:1.5pi,30:1.5pi'
bad_flow "cone of -20 pi" "vertex 0" "bound" -- "$ico" --scheme thurston \
  --cones '0:-20pi,3:pi,5:pi,9:pi'
bad_flow "malformed --cones curvature" "pix" -- "$ico" --cones '0:pi,3:pix'
bad_flow "malformed --cones item" "0pi" -- "$ico" --cones '0pi'
bad_flow "malformed --cones vertex" "-1" -- "$ico" --cones='-1:pi,0:pi,3:pi,5:pi,9:pi'
bad_flow "--cones vertex out of range" "vertex 5000" -- "$ico" --cones '5000:pi,0:pi,3:pi,5:pi'
bad_flow "--cones given twice at a vertex" "vertex 0" -- "$ico" --cones '0:pi,3:pi,5:pi,9:pi,0:pi'
printf '0 pi\n3 pi\n5 pi\n9 pi extra\n' >bad/cones.txt
bad_flow "malformed cone file" "cones.txt:4" -- "$ico" --cones bad/cones.txt
bad_flow "--cones with a non-flat target" "--cones" -- "$ico" --cones '0:pi,3:pi,5:pi,9:pi' --target uniform
bad_flow "--target neither name nor file" "--target" "nosuch" -- "$ico" --target nosuch
printf '1\n2\n' >bad/two_values.txt
bad_flow "--target FILE of the wrong length" "two_values.txt" "2 curvature values" -- \
  meshes/small_icosphere.obj --target bad/two_values.txt
printf '0\n0\nnot-a-number\n' >bad/word_values.txt
bad_flow "--target FILE with a word" "word_values.txt:3" -- meshes/small_icosphere.obj --target bad/word_values.txt
bad_flow "--scheme unknown" "foo" -- meshes/small_torus.obj --scheme foo
bad_flow "--solver unknown" "foo" -- meshes/small_torus.obj --solver foo
bad_flow "--init unknown" "foo" -- meshes/small_torus.obj --init foo
bad_flow "--boundary unknown" "foo" -- meshes/small_torus.obj --boundary foo
bad_flow "--tol negative" "--tol" -- meshes/small_torus.obj --tol -1
bad_flow "unknown flow option" "--frobnicate" -- meshes/small_torus.obj --frobnicate

# -o naming the input mesh is refused and leaves the mesh byte-identical.
cp meshes/small_torus.obj own.obj
own_sum="$(checksum own.obj)"
ricci flow own.obj -o own.obj
expect_rc "-o equal to the input" 2
expect_err "-o equal to the input" "own.obj" "overwrite"
expect_same "-o equal to the input leaves it untouched" own.obj "$own_sum"
ricci flow own.obj -o "./results/../own.obj"
expect_rc "-o equal to the input, spelled differently" 2
expect_same "-o equal to the input, spelled differently" own.obj "$own_sum"

# An existing result survives later failed runs that name it.
result_sum="$(checksum results/torus.json)"
for args in "bad/nonmanifold_edge.obj --strict" "bad/cut.ply" "bad/missing.obj" "$ico --cones 0:pi" \
  "meshes/small_torus.obj --target nosuch"; do
  # shellcheck disable=SC2086  # the arguments are split on purpose
  ricci flow $args -o results/torus.json
  expect_rc "failed run over an existing output ($args)" 2
  expect_same "failed run over an existing output ($args)" results/torus.json "$result_sum"
done
expect_no_temporaries "failed runs leave no temporaries" results

# --- param ---------------------------------------------------------------------------------------
mkdir -p param
ricci param --help
expect_rc "param --help" 0
expect_out "param --help" "--cones" "--boundary" "--report" "--quantize" "auto"
ricci param meshes/small_torus.obj --cones none -o param/torus_uv.obj --report param/torus.json
expect_rc "param torus" 0
expect_file "param torus writes the OBJ" param/torus_uv.obj
expect_json "param torus report" param/torus.json \
  'd["converged"] and d["cut"]["generators"] == 2 and len(d["layout"]["lattice"]) == 2 and d["distortion"]["flipped_faces"] == 0 and d["layout"]["max_length_relative_error"] <= 1e-9'
if "$PYTHON" - param/torus_uv.obj <<'EOF'
import sys
v = vt = f = 0
ok = True
for line in open(sys.argv[1]):
    w = line.split()
    if not w: continue
    if w[0] == "v": v += 1
    elif w[0] == "vt":
        vt += 1
        ok = ok and all(-1e-12 <= float(x) <= 1 + 1e-12 for x in w[1:3])
    elif w[0] == "f":
        f += 1
        ok = ok and all("/" in c for c in w[1:4])
sys.exit(0 if ok and v > 0 and vt > v and f > 0 else 1)
EOF
then ok; else fail "param torus OBJ" "v/vt/f layout wrong (vt must exceed v on a cut torus, all in [0,1])"; fi
ricci param "$ico" --cones 8 --quantize -o param/sphere_uv.obj --json
expect_rc "param sphere auto cones" 0
expect_out "param sphere auto cones" '"cones"' '"area_distortion_energy"'
ricci param meshes/small_disk.obj --cones none --boundary disk -o param/disk_uv.obj --report param/disk.json
expect_rc "param disk" 0
# Seams that may bend: the torus's generators carry its curvature, the report says how much.
ricci param meshes/small_torus.obj --seams free -o param/free_seams.obj --report param/free_seams.json
expect_rc "param --seams free" 0
expect_json "param --seams free report" param/free_seams.json \
  'd["converged"] and d["seams"]["mode"] == "free" and d["seams"]["curvature_max"] > 1e-3 and d["distortion"]["flipped_faces"] == 0'
expect_json "param rigid seams carry nothing" param/torus.json \
  'd["seams"]["mode"] == "rigid" and d["seams"]["curvature_max"] < 1e-8'
expect_json "param --seams free as promised: not compared with the rigid map" \
  param/free_seams.json 'not d["seams"]["rigid_kept"] and d["seams"]["rigid_area_energy"] == 0'
# Free seams whose map breaks down on needle-thin CAD faces give way to the rigid map, which
# distorts less; said on stderr and in the report.
ricci generate cad-cylinder -o param/cad_cylinder.obj
ricci param param/cad_cylinder.obj --seams free -o param/cad_free.obj --report param/cad_free.json
expect_rc "param --seams free on a CAD cylinder" 0
expect_err "the rigid map kept is said" "note:" "rigid seams are free seams"
expect_json "the report says which map was kept" param/cad_free.json \
  'd["seams"]["rigid_kept"] and d["seams"]["rigid_area_energy"] < d["seams"]["free_area_energy"] and d["seams"]["curvature_max"] < 1e-8 and any("free seams" in w for w in d["warnings"])'
# Two cones on genus 2, too few for the selection's bounds: two candidate sets measured on the
# flow, the better one's curvatures refined there; the report says which and by how much.
ricci generate surface --genus 2 --resolution 8 -o param/genus2.obj
ricci param param/genus2.obj --cones 2 -o param/genus2_uv.obj --report param/genus2.json
expect_rc "param genus 2 with 2 cones" 0
expect_json "its cone refinement is reported and helped" param/genus2.json \
  'd["cone_refinement"]["refined_area_energy"] <= min(d["cone_refinement"]["selected_area_energy"], d["cone_refinement"]["level_area_energy"]) and d["cone_refinement"]["kept"] in ("level", "selected") and d["cone_refinement"]["flows"] >= 2 and len(d["cones"]) == 2'
# Too few cones for an exact map of genus 12: said, with the remedy.
ricci generate surface --genus 12 --resolution 100 -o param/genus12.obj
ricci param param/genus12.obj --cones 8 -o param/genus12_uv.obj --report param/genus12.json
expect_err "param genus 12 with 8 rigid cones" "too few for an exact map" "try: --seams free"
expect_json "the report says so" param/genus12.json 'any("too few" in w for w in d["warnings"])'
ricci param meshes/small_torus.obj --seams bent -o param/bent.obj
expect_rc "param --seams bent" 2
expect_err "param --seams bent" "--seams" "rigid"
expect_no_file "param --seams bent writes nothing" param/bent.obj
expect_json "param disk report" param/disk.json 'd["converged"] and d["cut"]["cut_edges"] == 0'
# Files other tools open textured: the OBJ names its material, STEM.mtl its checkerboard STEM.png.
ricci param meshes/small_torus.obj -o param/textured.obj
expect_rc "param textured" 0
expect_file "param writes the material" param/textured.mtl
expect_file "param writes the checkerboard" param/textured.png
expect_in "the OBJ names its material" param/textured.obj "mtllib textured.mtl" "usemtl ricci_texture"
expect_in "the material names the checkerboard" param/textured.mtl "map_Kd textured.png"
cp param/textured.png param/brick.png
ricci param meshes/small_torus.obj -o param/own_texture.obj --texture param/brick.png
expect_in "--texture: the material names that image" param/own_texture.mtl "map_Kd brick.png"
expect_no_file "--texture: no checkerboard" param/own_texture.png
ricci param meshes/small_torus.obj -o param/plain.obj --texture none
expect_no_file "--texture none: no material" param/plain.mtl
if grep -q mtllib param/plain.obj; then fail "--texture none" "the OBJ names a material"; else ok; fi
ricci param meshes/small_torus.obj -o param/missing_texture.obj --texture param/nosuch.png
expect_rc "--texture missing" 2
expect_err "--texture missing" "nosuch.png" "try: --texture checker"
expect_no_file "--texture missing writes nothing" param/missing_texture.obj
# glTF binary: the magic, version 2, the texture inside.
ricci param meshes/small_torus.obj -o param/torus.glb
expect_rc "param glb" 0
"$PYTHON" - param/torus.glb <<'PY' && ok || fail "glb" "not a glTF 2 binary with an embedded PNG"
import json, struct, sys
data = open(sys.argv[1], "rb").read()
magic, version, length = struct.unpack_from("<4sII", data, 0)
assert magic == b"glTF" and version == 2 and length == len(data)
chunk_length, chunk_type = struct.unpack_from("<I4s", data, 12)
gltf = json.loads(data[20:20 + chunk_length])
assert chunk_type == b"JSON"
assert gltf["images"][0]["mimeType"] == "image/png"
assert "TEXCOORD_0" in gltf["meshes"][0]["primitives"][0]["attributes"]
PY
ricci param meshes/small_torus.obj -o param/refined.glb --faces refinement
expect_rc "glb of the refinement" 2
expect_err "glb of the refinement" "projective" "try: --format obj"
ricci param "$ico" --cones none -o param/refused.obj
expect_rc "param sphere without cones" 2
expect_err "param sphere without cones" "no flat metric without cones" "try: --cones auto"
expect_no_file "param sphere without cones writes nothing" param/refused.obj
ricci param "$ico" --cones 0:pi -o param/refused.obj
expect_rc "param sphere, cones breaking Gauss-Bonnet" 2
expect_err "param sphere, cones breaking Gauss-Bonnet" "Gauss-Bonnet" "try: --cones auto"
ricci param meshes/small_torus.obj --cones one -o param/refused.obj
expect_rc "param torus, one cone" 2
expect_err "param torus, one cone" "genus >= 2" "try: --cones needed, or --cones auto"
ricci param "$ico" --cones sideways -o param/refused.obj
expect_rc "param bad --cones" 2
expect_no_file "param bad --cones writes nothing" param/refused.obj
cp meshes/small_torus.obj param/own.obj
own_sum="$(checksum param/own.obj)"
ricci param param/own.obj --cones none -o param/own.obj
expect_rc "param -o equal to the input" 2
expect_same "param -o equal to the input leaves it" param/own.obj "$own_sum"
expect_no_temporaries "param leaves no temporaries" param

# --- sphere --------------------------------------------------------------------------------------
mkdir -p sphere
ricci sphere --help
expect_rc "sphere --help" 0
expect_out "sphere --help" "--pole" "--scheme" "--report" "--no-untangle"
ricci sphere meshes/icosphere.obj -o sphere/ico_sphere.obj --report sphere/ico.json
expect_rc "sphere icosphere" 0
expect_file "sphere icosphere writes the OBJ" sphere/ico_sphere.obj
expect_json "sphere icosphere report" sphere/ico.json \
  'd["converged"] and d["invariants"]["inverted_faces"] == 0 and d["invariants"]["max_radius_deviation"] <= 1e-12 and abs(d["invariants"]["spherical_area_error"]) <= 1e-8 and d["normalisation"]["centre_of_mass"] <= 1e-9'
if "$PYTHON" - sphere/ico_sphere.obj meshes/icosphere.obj <<'EOF'
import sys
def read(path):
    v, f = [], []
    for line in open(path):
        w = line.split()
        if w and w[0] == "v": v.append([float(x) for x in w[1:4]])
        elif w and w[0] == "f": f.append([c.split("/")[0] for c in w[1:4]])
    return v, f
v, f = read(sys.argv[1])
v0, f0 = read(sys.argv[2])
ok = len(v) == len(v0) and f == f0 and all(abs(sum(x * x for x in p) ** 0.5 - 1) < 1e-12 for p in v)
sys.exit(0 if ok else 1)
EOF
then ok; else fail "sphere OBJ" "vertices not on the unit sphere or faces differ from the input's"; fi
ricci sphere meshes/tetrahedron.obj -o sphere/tet_sphere.obj --pole 2 --scheme inversive-distance --json
expect_rc "sphere tetrahedron --pole --scheme --json" 0
expect_json "sphere tetrahedron --json" "$WORK/out.txt" \
  'd["pole"] == 2 and d["pole_file_index"] == 2 and d["scheme"] == "inversive-distance" and d["invariants"]["inverted_faces"] == 0'
ricci sphere meshes/small_torus.obj -o sphere/refused.obj
expect_rc "sphere torus" 2
expect_err "sphere torus" "genus 1"
expect_no_file "sphere torus writes nothing" sphere/refused.obj
ricci sphere meshes/small_disk.obj -o sphere/refused.obj
expect_rc "sphere disk" 2
expect_err "sphere disk" "boundary loop"
expect_no_file "sphere disk writes nothing" sphere/refused.obj
ricci sphere meshes/icosphere.obj -o sphere/refused.obj --pole 100000
expect_rc "sphere bad --pole" 2
expect_err "sphere bad --pole" "--pole: vertex 100000"
expect_no_file "sphere bad --pole writes nothing" sphere/refused.obj
cp meshes/small_icosphere.obj sphere/own.obj
own_sum="$(checksum sphere/own.obj)"
ricci sphere sphere/own.obj -o sphere/own.obj
expect_rc "sphere -o equal to the input" 2
expect_same "sphere -o equal to the input leaves it" sphere/own.obj "$own_sum"
# Long fingers (tips at e^-50 in area): the layout runs wider than double, and the map is an
# embedding; the report says how far the log area ratio reaches and in what precision.
ricci generate fingers --finger-length 4 -o sphere/fingers.obj
expect_rc "generate fingers" 0
ricci sphere sphere/fingers.obj -o sphere/fingers_sphere.obj --report sphere/fingers.json
expect_rc "sphere fingers" 0
expect_out "sphere fingers" "inverted faces 0" "precision 113 bits" "log area ["
expect_json "sphere fingers report" sphere/fingers.json \
  'd["valid"] and d["invariants"]["inverted_faces"] == 0 and d["distortion"]["log_area_min"] < -45 and d["precision"]["bits"] == 113 and d["precision"]["unresolved_faces"] == 0'
# Twice as far: the tips fall below double resolution on the unit sphere. Exit 3, no OBJ, the
# report written with finite figures, and the message says why and what works instead.
ricci generate fingers --finger-length 6 -o sphere/long_fingers.obj
ricci sphere sphere/long_fingers.obj -o sphere/refused.obj --report sphere/long_fingers.json
expect_rc "sphere fingers below double resolution" 3
expect_err "sphere fingers below double resolution" "by rounding to double" \
  "below double resolution" "try: ricci param"
expect_no_file "sphere fingers below double resolution writes no OBJ" sphere/refused.obj
expect_json "sphere fingers below double resolution report" sphere/long_fingers.json \
  'not d["valid"] and d["converged"] and d["invariants"]["inverted_by_rounding"] > 0 and d["precision"]["unresolved_faces"] > 0 and d["distortion"]["log_area_min"] < -70 and all(isinstance(x, float) and math.isfinite(x) for x in d["distortion"].values())'
# Needles and valence-3 vertices: vertex scaling reverses needles; untangling frees them.
ricci generate icosphere --resolution 3 --valence3 --needles 0.998 -o sphere/needles.obj
ricci sphere sphere/needles.obj -o sphere/needles_sphere.obj --json
expect_rc "sphere needles" 0
expect_json "sphere needles --json" "$WORK/out.txt" \
  'd["valid"] and d["invariants"]["inverted_faces"] == 0 and d["untangle"]["vertices"] > 0 and d["disk"]["reversed_faces"] > 0'
ricci sphere sphere/needles.obj -o sphere/refused.obj --no-untangle
expect_rc "sphere needles --no-untangle" 3
expect_err "sphere needles --no-untangle" "reversed in the disk's flat metric" "untangling was off"
expect_no_file "sphere needles --no-untangle writes no OBJ" sphere/refused.obj
expect_no_temporaries "sphere leaves no temporaries" sphere

# --- hyperbolic: flow and param with --geometry hyperbolic (chi < 0) ----------------------------
mkdir -p hyperbolic
ricci generate surface --genus 2 -o hyperbolic/g2.obj
expect_rc "generate genus 2 for hyperbolic" 0
ricci generate surface --genus 0 --holes 3 -o hyperbolic/pants.obj
expect_rc "generate pair of pants" 0
flow_ok "genus 2 hyperbolic" hyperbolic/g2.obj --geometry hyperbolic
# Gauss-Bonnet in curvature -1 with K = 0: area = -2 pi chi = 4 pi.
expect_json "flow genus 2 hyperbolic area" flow.json \
  'd["geometry"] == "hyperbolic" and abs(d["components"][0]["total_area"] - 4 * math.pi) <= 1e-6'
ricci flow hyperbolic/g2.obj --geometry hyperbolic --scheme virtual-radius
expect_rc "flow hyperbolic virtual-radius" 2
expect_err "flow hyperbolic virtual-radius" "virtual-radius"
ricci flow meshes/small_torus.obj --geometry hyperbolic
expect_rc "flow hyperbolic torus" 2
expect_err "flow hyperbolic torus" "chi" "try: --geometry euclidean"
ricci flow hyperbolic/g2.obj --geometry spherical
expect_rc "flow --geometry spherical" 2
# A pair of pants: the default hyperbolic boundary is geodesic (zero curvature on it too).
flow_ok "pants hyperbolic" hyperbolic/pants.obj --geometry hyperbolic -o hyperbolic/pants.json
expect_json "flow pants hyperbolic: K = 0 at every vertex, boundary included" hyperbolic/pants.json \
  'len(d["vertex_data"]["curvature"]) > 0 and max(abs(k) for k in d["vertex_data"]["curvature"]) <= 1e-10 and abs(d["components"][0]["total_area"] - 2 * math.pi) <= 1e-6'
pictures=()
ricci render --help
[[ "$rc" == 0 ]] && pictures=(--pictures hyperbolic/pics)
ricci param hyperbolic/g2.obj --geometry hyperbolic -o hyperbolic/out.obj \
  --report hyperbolic/r.json "${pictures[@]}"
expect_rc "param genus 2 hyperbolic" 0
expect_file "param genus 2 hyperbolic writes the OBJ" hyperbolic/out.obj
expect_json "param genus 2 hyperbolic report" hyperbolic/r.json \
  'd["converged"] and d["fuchsian_group"]["genus"] == 2 and d["fuchsian_group"]["relation_residual"] < 1e-8 and len(d["fuchsian_group"]["a"]) == 2 and d["layout"]["max_radius"] < 1'
if "$PYTHON" - hyperbolic/out.obj <<'EOF'
import sys
vt = [[float(x) for x in line.split()[1:3]] for line in open(sys.argv[1]) if line.startswith("vt ")]
sys.exit(0 if vt and all(u * u + v * v < 1 for u, v in vt) else 1)
EOF
then ok; else fail "param hyperbolic OBJ" "no vt lines, or one outside the unit disk"; fi
if (( ${#pictures[@]} )); then
  for picture in tiling.svg tiling.png; do
    if [[ -s "hyperbolic/pics/$picture" ]]; then ok; else
      fail "param hyperbolic --pictures" "hyperbolic/pics/$picture missing or empty"
    fi
  done
fi
if grep -q "warning" "$WORK/err.txt"; then
  fail "param genus 2 hyperbolic: no warning" "$(first_error)"
else ok; fi
# A genus-3 surface with 60 holes (hyperbolic area 402): its layout reaches the rim of the disk
# further than double precision resolves. The OBJ is written, with a warning that says so (and,
# with --pictures, that the tiling cannot be drawn) instead of a silent answer or a failure.
ricci generate surface --genus 3 --holes 60 --resolution 48 -o hyperbolic/holes60.obj
ricci param hyperbolic/holes60.obj --geometry hyperbolic -o hyperbolic/holes60_uv.obj "${pictures[@]/pics/pics60}"
expect_rc "param hyperbolic beyond double precision" 0
expect_file "param hyperbolic beyond double precision writes the OBJ" hyperbolic/holes60_uv.obj
expect_err "param hyperbolic beyond double precision" "warning: hyperbolic/holes60.obj: the layout reaches |z| = 1 - " \
  "where double precision cannot keep points apart"
if (( ${#pictures[@]} )); then
  expect_err "param hyperbolic beyond double precision --pictures" "warning: pictures: the tiling is not drawn"
fi
ricci param meshes/small_torus.obj --geometry hyperbolic -o hyperbolic/x.obj
expect_rc "param hyperbolic torus" 2
expect_err "param hyperbolic torus" "chi"
expect_no_file "param hyperbolic torus writes nothing" hyperbolic/x.obj
ricci param hyperbolic/g2.obj --geometry hyperbolic --cones 3 -o hyperbolic/y.obj
expect_rc "param hyperbolic --cones" 2
expect_err "param hyperbolic --cones" "no cones"
expect_no_file "param hyperbolic --cones writes nothing" hyperbolic/y.obj
ricci param hyperbolic/pants.obj --geometry hyperbolic --scheme vertex-scaling -o hyperbolic/pants_uv.obj --json
expect_rc "param pants hyperbolic" 0
expect_json "param pants hyperbolic: no group" "$WORK/out.txt" \
  'd["converged"] and "fuchsian_group" not in d and d["layout"]["max_radius"] < 1'
# Hyperbolic intrinsic Delaunay flips (vertex scaling, the default --flips auto): the flow flips,
# and param writes the input's own faces (one per input face, all vt in the disk) with the group.
flow_ok "genus 2 hyperbolic vertex scaling flips" hyperbolic/g2.obj --geometry hyperbolic \
  --scheme vertex-scaling
expect_json "flow hyperbolic flips" flow.json \
  'd["flips"] == "auto" and d["flipped_edges"] > 0 and abs(d["components"][0]["total_area"] - 4 * math.pi) <= 1e-6'
ricci param hyperbolic/g2.obj --geometry hyperbolic --scheme vertex-scaling \
  -o hyperbolic/flipped.obj --report hyperbolic/flipped.json
expect_rc "param hyperbolic with flips" 0
expect_out "param hyperbolic with flips" "edges flipped"
expect_json "param hyperbolic with flips report" hyperbolic/flipped.json \
  'd["flow"]["flipped_edges"] > 0 and d["fuchsian_group"]["relation_residual"] < 1e-10 and d["layout"]["development_length_mismatch"] < 1e-14'
if "$PYTHON" - hyperbolic/g2.obj hyperbolic/flipped.obj <<'EOF'
import sys
def faces(path):
    return [[int(c.split("/")[0]) for c in line.split()[1:]] for line in open(path) if line.startswith("f ")]
vt = [[float(x) for x in line.split()[1:3]] for line in open(sys.argv[2]) if line.startswith("vt ")]
sys.exit(0 if faces(sys.argv[1]) == faces(sys.argv[2]) and vt and all(u * u + v * v < 1 for u, v in vt) else 1)
EOF
then ok; else fail "param hyperbolic with flips OBJ" "faces differ from the input's, or a vt outside the disk"; fi
expect_no_temporaries "hyperbolic leaves no temporaries" hyperbolic

# --- interrupts: SIGINT leaves neither output nor temporary files ------------------------------
# The program runs under a wrapper that restores SIGINT's default action (a background job of a
# non-interactive shell starts with SIGINT ignored, and ricci then keeps ignoring it); exec keeps
# the process id, so $! is ricci's.
ricci_in_background() {  # ricci_in_background ARGS...: starts ricci, its id in $pid
  "$PYTHON" -c 'import os, signal, sys
signal.signal(signal.SIGINT, signal.SIG_DFL)
os.execv(sys.argv[1], sys.argv[1:])' "$RICCI" "$@" >/dev/null 2>"$WORK/err.txt" &
  pid=$!
}
mkdir -p interrupt
ricci generate torus --resolution 100 -o interrupt/big_torus.obj
expect_rc "generate a big torus" 0

# Interrupted while computing: exit 130 (128 + SIGINT), no output, no temporaries.
ricci_in_background flow interrupt/big_torus.obj --solver gradient --max-iterations 200000 \
  -o interrupt/computing.json
sleep 1
kill -INT "$pid"
wait "$pid"
rc=$?
expect_rc "SIGINT while computing" 130
expect_no_file "SIGINT while computing writes nothing" interrupt/computing.json
expect_no_temporaries "SIGINT while computing leaves no temporaries" interrupt

# Interrupted while writing: a named pipe stands in for the writer's temporary file (its name is
# `.<target>.tmp.<pid>.0`), so the write blocks once the pipe's buffer is full; SIGINT must then
# remove the temporary, leave no output and exit 130.
ricci_in_background flow interrupt/big_torus.obj -o interrupt/writing.json
fifo="interrupt/.writing.json.tmp.$pid.0"
mkfifo "$fifo"
"$PYTHON" - "$fifo" "$pid" interrupt/writing.json <<'EOF'
import os, select, signal, sys, time
fifo, pid, target = sys.argv[1], int(sys.argv[2]), sys.argv[3]
fd = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)
deadline = time.time() + 120
while time.time() < deadline:
    if os.path.exists(target):
        sys.exit(3)  # the run finished before the pipe was in place
    readable, _, _ = select.select([fd], [], [], 0.2)
    if readable and os.read(fd, 1):
        break  # the program is writing into the pipe (and blocks when its buffer is full)
else:
    sys.exit(4)
time.sleep(0.2)
os.kill(pid, signal.SIGINT)
while os.path.exists(fifo) and time.time() < deadline:
    time.sleep(0.05)
os.close(fd)
EOF
sync_rc=$?
wait "$pid"
rc=$?
if [[ "$sync_rc" == 3 ]]; then
  echo "note: SIGINT while writing not checked: the run finished before the pipe was made"
  rm -f "$fifo" interrupt/writing.json
elif [[ "$sync_rc" != 0 ]]; then
  fail "SIGINT while writing" "the program never wrote into the pipe (status $sync_rc)"
  rm -f "$fifo"
else
  ok
  expect_rc "SIGINT while writing" 130
  expect_no_file "SIGINT while writing removes the temporary" "$fifo"
  expect_no_file "SIGINT while writing writes no output" interrupt/writing.json
  expect_no_temporaries "SIGINT while writing leaves no temporaries" interrupt
fi

# --- spline --------------------------------------------------------------------------------------
mkdir -p spline
spline_pictures=()
ricci render --help
[[ "$rc" == 0 ]] && spline_pictures=(--pictures spline/pics)
ricci spline meshes/torus.obj -o spline/torus.obj --control-net spline/net.obj --report spline/report.json \
  "${spline_pictures[@]}"
expect_rc "spline torus" 0
if (( ${#spline_pictures[@]} )); then
  expect_err "spline --pictures" "pictures:" "spline/pics/control_net.png"
  for picture in domain.png control_net.png surface.png layout.png; do
    if [[ "$(head -c 8 "spline/pics/$picture" 2>/dev/null | od -An -tx1 | tr -d ' \n')" == \
          89504e470d0a1a0a ]]; then ok; else
      fail "spline --pictures" "spline/pics/$picture missing or not a PNG"
    fi
  done
fi
expect_file "spline surface" spline/torus.obj
expect_file "spline control net" spline/net.obj
expect_out "spline torus" "C1 jumps" "error / bbox diagonal"
expect_json "spline report" spline/report.json \
  'd["converged"] and d["continuity"]["relative_gradient_jump"] < 1e-9 and 0 < d["error"]["max_distance"] < 0.05 and d["surface"]["faces"] == 24 * 4096'
ricci spline meshes/torus.obj -o spline/x.obj --refine 0
expect_rc "spline --refine 0" 2
expect_no_file "spline --refine 0 writes nothing" spline/x.obj
ricci spline meshes/torus.obj -o meshes/torus.obj
expect_rc "spline -o naming the input" 2

# --- summary -----------------------------------------------------------------------------------
finish
