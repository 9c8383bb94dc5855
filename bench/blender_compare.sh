#!/usr/bin/env bash
# ricci's Blender add-on against Blender's own unwrap (bench/blender_compare.py, run inside a
# headless Blender): the add-on zip from `ricci blender-addon`, unpacked into a user-scripts
# folder under OUT_DIR (nothing installed for the user), then every mesh of ../shared/meshes
# that ricci parameterizes by default and some of ../shared/corpus (quads, CAD, scans), and
# Suzanne rendered with each map (OUT_DIR/suzanne-*.png).
#
#   bench/blender_compare.sh [BUILD_DIR] [OUT_DIR]
#   RICCI_BLENDER_MESHES="a.obj b.off" ...   only these files
set -euo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=bench/lib.sh
source bench/lib.sh
bench_paths blender_compare "$@"
corpus=$PWD/../shared/corpus
command -v blender >/dev/null || { echo "blender_compare: no blender (apt install blender)" >&2; exit 2; }
[ -f "$checkuv" ] || { echo "blender_compare: $checkuv missing" >&2; exit 2; }
mkdir -p "$out/scripts/addons"
out=$(cd "$out" && pwd)
"$ricci" blender-addon -o "$out/ricci_uv.zip" >/dev/null
rm -rf "$out/scripts/addons/ricci_uv"
/usr/bin/python3 -c "import sys, zipfile; zipfile.ZipFile(sys.argv[1]).extractall(sys.argv[2])" \
  "$out/ricci_uv.zip" "$out/scripts/addons"

if [ -n "${RICCI_BLENDER_MESHES:-}" ]; then
  read -r -a meshes <<<"$RICCI_BLENDER_MESHES"
else
  meshes=()
  for m in spot.obj bunny.obj kitten.obj face.obj camelhead.off beetle.obj bob_tri.obj \
    fertility.off eight.off 3holes.off punctured-torus.obj; do
    [ -f "$shared/$m" ] && meshes+=("$shared/$m")
  done
  for m in libigl__libigl-tutorial-data/horse_quad.obj libigl__libigl-tutorial-data/fandisk.off \
    libigl__libigl-tutorial-data/cow.off libigl__libigl-tutorial-data/cheburashka.off \
    libigl__libigl-tutorial-data/inspired_mesh_quads_Smooth.off \
    nmwsharp__geometry-central/test__assets__lego.ply; do
    [ -f "$corpus/$m" ] && meshes+=("$corpus/$m")
  done
fi
BLENDER_USER_SCRIPTS="$out/scripts" BLENDER_USER_CONFIG="$out/config" \
  blender -b --factory-startup --addons ricci_uv --python-exit-code 1 \
  -P bench/blender_compare.py -- "$out" "$checkuv" --picture "${meshes[@]}" 2>&1 |
  grep -v -E '^(Info|Fra:|Saved|OBJ|Writing| Time|$)'
