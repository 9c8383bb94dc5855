#!/usr/bin/env bash
# The common refinement (`ricci param --faces refinement`, docs/parameterization.md) on the shared
# meshes: sizes beside the input's, flips undone, the largest intrinsic-length error of the
# texture coordinates, the refinement's own time, and checkuv.py on the linear-uv file.
#   bench/refinement.sh [RICCI] [SHARED_MESHES] [OUT_DIR] [MESH...]
# MESH defaults to face.obj bunny.obj kitten.obj; every run uses --scheme vertex-scaling and
# automatic cones.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
ricci=${1:-$here/build/ricci}
meshes=${2:-$here/../shared/meshes}
out=${3:-$here/build/refinement}
shift $(($# < 3 ? $# : 3))
list=("$@")
((${#list[@]})) || list=(face.obj bunny.obj kitten.obj)
checkuv=${CHECKUV:-$here/../shared/tools/checkuv.py}
mkdir -p "$out"
[ -d "$meshes" ] || { echo "refinement: $meshes not found" >&2; exit 1; }

echo "| mesh | input V / F | refinement V / F | flips (isometric + Ptolemy) | points (T0xT1, T1xT', T0xT') | length error | inverted | refinement s | param s | checkuv linear: flipped, degenerate, cones, angle distortion mean |"
echo "|---|---|---|---|---|---|---|---|---|---|"
for mesh in "${list[@]}"; do
  stem="$out/${mesh%.*}"
  "$ricci" param "$meshes/$mesh" --scheme vertex-scaling --faces refinement -o "$stem.obj" \
    --report "$stem.json" >/dev/null
  check="{}"
  [ -f "$checkuv" ] && check=$(python3 "$checkuv" "$stem.linear.obj")
  python3 - "$mesh" "$stem.json" "$check" <<'EOF'
import json, sys
mesh, report, check = sys.argv[1], json.load(open(sys.argv[2])), json.loads(sys.argv[3])
r = report["refinement"]
p = r["points"]
c = (f"{check['flipped']}, {check['degenerate']}, {check['cones']}, "
     f"{check['angle_distortion_mean']:.4f}") if check else "n/a"
print(f"| {mesh} | {r['input_vertices']} / {r['input_faces']} | {r['vertices']} / {r['triangles']} "
      f"| {r['isometric_flips']} + {r['ptolemy_flips']} | {p['input_x_delaunay']}, "
      f"{p['delaunay_x_intrinsic']}, {p['input_x_intrinsic']} | "
      f"{r['max_intrinsic_length_error']:.2e} | {r['inverted_triangles']} | {r['seconds']:.2f} | "
      f"{report['seconds']:.1f} | {c} |")
EOF
done
