#!/usr/bin/env bash
# Reproduces the tutorial's parameterization experiments (its figures 8-22) on the real meshes
# of ../shared/meshes that resemble its models, and writes the table of docs/experiments.md: each
# experiment with the tutorial's Thurston packing and with ricci's default (vertex scaling with
# intrinsic Delaunay flips, on the input's own faces).
#   bench/experiments.sh [RICCI] [SHARED_MESHES] [OUT_DIR]
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
ricci=${1:-$here/build/ricci}
meshes=${2:-$here/../shared/meshes}
out=${3:-$here/build/experiments}
mkdir -p "$out"
[ -d "$meshes" ] || { echo "experiments: $meshes not found" >&2; exit 1; }

# name | mesh | ricci param options | the tutorial's model and figure | its area distortion
experiments=(
  "face-disk|face.obj|--cones none --boundary disk|David head 15k faces, disk boundary 2 pi/m (fig. 9)|0.960747"
  "camelhead-disk|camelhead.off|--cones none --boundary disk|(same set-up as fig. 9)|"
  "face-free|face.obj|--cones none --boundary free|(free boundary, tutorial section 5.2)|"
  "bob-none|bob_tri.obj|--cones none|rocker arm 1k / 5k faces, genus 1, no cones (fig. 15)|0.554323 / 0.576723"
  "bob-none-exact|bob_tri.obj|--cones none --scheme inversive-distance|(the same, with the metric that reproduces the input lengths)|"
  "kitten-none|kitten.obj|--cones none|(genus 1, no cones, 106k faces)|"
  "3holes-one|3holes.off|--cones one|3 holes 10k faces / sculpture 2k and 10k faces, one cone of -8 pi (figs. 8, 20, 21)|0.658119 / 1.000959"
  "eight-one|eight.off|--cones one|(genus 2, one cone of -4 pi)|"
  "fertility-auto|fertility.off|--cones 6 --quantize|genus-6 buddha 10k faces, five cones of -4 pi (fig. 22)|1.467170"
  "spot-auto|spot.obj|--cones 8 --quantize|Iphigenia 30k faces, 8 cones (fig. 13)|0.571903"
  "spot-8|spot.obj|--cones 8|(8 automatic cones, not quantized: docs/cones.md)|"
  "face-8|face.obj|--cones 8|(free boundary and 8 automatic cones)|"
  "bob-4|bob_tri.obj|--cones 4|(genus 1, 4 automatic cones)|"
  "kitten-8|kitten.obj|--cones 8|(genus 1, 8 automatic cones)|"
  "3holes-16|3holes.off|--cones 16|(genus 3, 16 automatic cones)|"
  "eight-8|eight.off|--cones 8|(genus 2, 8 automatic cones)|"
  "fertility-16|fertility.off|--cones 16|(genus 4, 16 automatic cones)|"
)

table="$out/table.md"
{
  echo "| model (ours) | scheme | faces | topology | cones (curvature / pi) | area distortion (eq. 9) | angle distortion mean / max | flipped | seconds | the tutorial's model | its area distortion |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|"
} > "$table"
for row in "${experiments[@]}"; do
  IFS='|' read -r name mesh opts theirs their_value <<< "$row"
  [ -f "$meshes/$mesh" ] || { echo "experiments: skipping $mesh (missing)" >&2; continue; }
  schemes="thurston vertex-scaling"
  [[ "$opts" == *--scheme* ]] && schemes="given"  # the row names its own scheme
  for scheme in $schemes; do
  run="$name-$scheme"
  scheme_option=(--scheme "$scheme")
  # The tutorial's rows draw its map as it does: without ricci's angle polish.
  [ "$scheme" = thurston ] && scheme_option+=(--polish none)
  [ "$scheme" = given ] && scheme_option=()
  # shellcheck disable=SC2086
  if ! "$ricci" param "$meshes/$mesh" $opts "${scheme_option[@]}" -o "$out/$run.obj" --report "$out/$run.json" > "$out/$run.log" 2>&1; then
    echo "experiments: $run did not finish: $(tail -1 "$out/$run.log")" >&2
  fi
  /usr/bin/python3 - "$out/$run.json" "$mesh" "$opts" "$theirs" "$their_value" "$scheme" >> "$table" <<'PY'
import json, sys
path, mesh, opts, theirs, their_value, scheme = sys.argv[1:]
scheme = {"vertex-scaling": "vertex-scaling (default)", "thurston": "thurston (tutorial)"}.get(scheme, "as given")
try:
    r = json.load(open(path))
except (OSError, ValueError):
    print(f"| {mesh} `{opts}` | {scheme} | | | | failed | | | | {theirs} | {their_value} |")
    sys.exit(0)
flow = r["flow"]
comp = flow["components"][0]
topo = f"genus {comp['genus']}, {comp['boundary_loops']} boundary loops"
if not r["converged"]:
    print(f"| {mesh} `{opts}` | {scheme} | {flow['faces']} | {topo} | | not converged: {r['message'][:60]} | | | {r['seconds']:.2f} | {theirs} | {their_value} |")
    sys.exit(0)
d = r["distortion"]
cones = ", ".join(f"{c['curvature_over_pi']:.2f}" for c in r["cones"]) or "none"
if len(r["cones"]) > 8:
    cones = f"{len(r['cones'])} cones"
splits = r["modification"]["edge_splits"]
faces = f"{flow['faces']}" + (f" ({splits} splits)" if splits else "")
print(f"| {mesh} `{opts}` | {scheme} | {faces} | {topo} | {cones} | {d['area_distortion_energy']:.4f} | "
      f"{d['angle_distortion_mean']:.3f} / {d['angle_distortion_max']:.2f} | {d['flipped_faces']} | "
      f"{r['seconds']:.2f} | {theirs} | {their_value} |")
PY
  done
done
cat "$table"
