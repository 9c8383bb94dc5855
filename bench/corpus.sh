#!/usr/bin/env bash
# The corpus benchmark: `ricci batch` with default options over ../shared/corpus (157 real meshes
# from public repositories: CAD parts, scans, high genus, open surfaces, polygon and
# multi-component models, non-manifold files, odd file variants; MANIFEST.tsv gives the source,
# license and topology of each), every UV OBJ then checked by ../shared/tools/checkuv.py, which
# shares no code with ricci. Prints per class of MANIFEST.tsv (closed genus 0, 1, 2-9, >= 10,
# open, polygon faces, several components, non-manifold): meshes, ok (exit 0), clean (0 flipped
# faces and seams <= 1e-6 by the checker), seams <= 1e-9, flipped faces, seconds (sum of the
# per-mesh child seconds) and the routes the components' layouts took (flow, untangled, charts,
# unfolded, patches); then the slowest meshes and every mesh that is not clean, with why.
#
# Usage: RICCI=build/ricci [JOBS=2] [THREADS=1] bash bench/corpus.sh [SCRATCH_DIR] [CORPUS_DIR]
#        (scratch default build/bench-corpus, emptied first; corpus default ../shared/corpus).
# Extra options of ricci param go in RICCI_PARAM_OPTIONS (e.g. "--cones auto"). Takes about
# 3 minutes on two cores with JOBS=2 THREADS=1. Writes the table to SCRATCH_DIR/table.md and
# the per-mesh rows to SCRATCH_DIR/rows.json.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
ricci=${RICCI:-$here/build/ricci}
scratch=${1:-$here/build/bench-corpus}
corpus=${2:-$here/../shared/corpus}
jobs=${JOBS:-2}
threads=${THREADS:-1}
python=/usr/bin/python3
[ -x "$ricci" ] || { echo "corpus.sh: $ricci is not executable (set RICCI)" >&2; exit 1; }
[ -f "$corpus/MANIFEST.tsv" ] || { echo "corpus.sh: no corpus at $corpus (MANIFEST.tsv)" >&2; exit 1; }
checkuv=${CHECKUV:-$(cd "$here/.." && pwd)/shared/tools/checkuv.py}
[ -f "$checkuv" ] || { echo "corpus.sh: the checker $checkuv is missing (set CHECKUV)" >&2; exit 1; }
rm -rf "$scratch"
mkdir -p "$scratch"
# shellcheck disable=SC2086
start=$(date +%s.%N)
"$ricci" batch "$corpus" -o "$scratch/out" --jobs "$jobs" --threads "$threads" --timeout 900 \
  ${RICCI_PARAM_OPTIONS:-} >"$scratch/batch.log" 2>&1 || true
wall=$(echo "$(date +%s.%N) - $start" | bc)
echo "ricci batch over $corpus: ${wall%.*} s wall, $jobs jobs x $threads threads ($("$ricci" --version | head -1))"
echo
CHECKUV="$checkuv" "$python" "$here/bench/corpus_table.py" "$corpus" "$scratch/out" \
  --json "$scratch/rows.json" --jobs "$jobs" | tee "$scratch/table.md"
