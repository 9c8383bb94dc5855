#!/usr/bin/env bash
# Every command with its default options on every manifold mesh of ../shared/meshes (when
# present) and on generated hard cases: CAD strips and fans, valence-3 vertices, 0.1-degree
# needles, high genus, hundreds of holes. What a new user runs first must work everywhere:
#   flow     exits 0 and converges (to the tolerance, or at the floating-point floor);
#   param    exits 0, writes the input's own vertices and faces, and ../shared/tools/checkuv.py
#            agrees: seams match, the cones it reads back are the report's, no degenerate face,
#            and no flipped face but where noted below;
#   sphere   (closed genus 0) exits 0;
#   spline   exits 0;
#   flow/param --geometry hyperbolic (closed genus >= 2) exit 0, the Fuchsian relation to 1e-10
#            on the shared meshes.
# Usage: RICCI=build/ricci [RICCI_SWEEP_SHARD=K/N] bash tests/cli/defaults_test.sh [SCRATCH_DIR]
#   RICCI_SWEEP_SHARD=K/N runs only shard K of N (cases dealt by file size; ctest runs the sweep
#   as two shards, so that both cores share it).
set -u
here="$(cd "$(dirname "$0")" && pwd)"
source "$here/check_framework.sh" defaults_test "${1:-}"

shared="${RICCI_SHARED_MESHES:-$here/../../../shared/meshes}"
checkuv="$here/../../../shared/tools/checkuv.py"

# Flipped uv faces allowed per mesh, and why. Each vertex sits at its exact image under the
# flat metric and each face is drawn straight between them: a face the exact map bends strongly
# folds. igea: one 164-degree sliver next to a spiky vertex (u jumps by 0.26 across it);
# needles-genus2: vertices pulled 99.8 % of the way onto a neighbour; valence3-sphere: vertices
# lifted off the sphere inside its faces, each a spike the flat metric must open to 2 pi.
declare -A allowed_flips=([igea_tri]=1 [needles-genus2]=8 [valence3-sphere]=4)
declare -A allowed_inverted=([igea_tri]=1 [cad-cylinder]=200)
# Degenerate uv faces (zero area to checkuv's 1e-14 of the total): the free-boundary map of the
# Stanford bunny shrinks the region between its bottom holes by about e^-16, below that.
declare -A allowed_degenerate=([stanford-bunny]=1)
# Files the manifest calls manifold that --strict refuses as input, with the reason; by default
# they are repaired (degtri_sliding: a chain of zero-area slivers) and go on like the others.
declare -A refused=([degtri_sliding]="zero area")

cases=()
if [[ -f "$shared/MANIFEST.tsv" ]]; then
  while IFS=$'\t' read -r file _ _ _ _ _ _ loops _ genus manifold _; do
    [[ "$manifold" == "yes" ]] || continue
    [[ "$genus" =~ ^[0-9]+$ ]] || continue
    [[ -f "$shared/$file" ]] || continue
    cases+=("${file%.*} $shared/$file $genus $loops shared")
  done < <(tail -n +2 "$shared/MANIFEST.tsv")
else
  echo "note: $shared not found: generated meshes only"
fi
[[ -f "$checkuv" ]] || echo "note: $checkuv not found: the checkuv checks are skipped"
mkdir -p generated
generate() {  # name genus loops generate-arguments...
  local name=$1 genus=$2 loops=$3
  shift 3
  if "$RICCI" generate "$@" -o "generated/$name.obj" >/dev/null 2>gen.err; then
    cases+=("$name generated/$name.obj $genus $loops generated")
  else
    fail "generate $name" "$(cat gen.err)"
  fi
}
generate cad-cylinder 0 0 cad-cylinder --resolution 240
generate cad-ring 1 0 cad-ring --resolution 240
generate valence3-sphere 0 0 icosphere --resolution 4 --valence3
generate needles-genus2 2 0 surface --genus 2 --resolution 40 --needles 0.998
generate needles-disk 0 1 disk --resolution 40 --needles 0.998
generate genus-20 20 0 surface --genus 20 --resolution 41
generate genus-50 50 0 surface --genus 50 --resolution 101
generate holes-300 0 300 surface --genus 0 --holes 300 --resolution 60

json_true() {  # name file python-expression over d
  if "$PYTHON" -c "import json,sys; d=json.load(open(sys.argv[1])); sys.exit(0 if ($3) else 1)" "$2" \
    2>/dev/null; then
    ok
  else
    fail "$1" "false: $3 ($(head -c 300 "$2"))"
  fi
}
run() {  # name expected-rc command...
  local name=$1 expected=$2
  shift 2
  "$@" >out.json 2>err.txt
  local rc=$?
  if [[ $rc -eq $expected ]]; then ok; else fail "$name" "exit $rc, expected $expected: $(head -c 300 err.txt)"; fi
  return $rc
}

shard=${RICCI_SWEEP_SHARD:-0/1}
shard_index=${shard%/*} shard_count=${shard#*/}
if ! [[ "$shard_index" =~ ^[0-9]+$ && "$shard_count" =~ ^[1-9][0-9]*$ ]] ||
  ((shard_index >= shard_count)); then
  echo "defaults_test: RICCI_SWEEP_SHARD must be K/N with 0 <= K < N, got '$shard'" >&2
  exit 2
fi
# Cases dealt to shards by file size, largest first, each to the shard with the fewest bytes so
# far (the size stands for the work: the 270k-face scan alone is a third of the sweep).
declare -a shard_bytes shard_of
for ((k = 0; k < shard_count; ++k)); do shard_bytes[k]=0; done
while read -r bytes index; do
  best=0
  for ((k = 1; k < shard_count; ++k)); do
    ((shard_bytes[k] < shard_bytes[best])) && best=$k
  done
  shard_of[index]=$best
  shard_bytes[best]=$((shard_bytes[best] + bytes))
done < <(for index in "${!cases[@]}"; do
  read -r _ path _ <<<"${cases[$index]}"
  echo "$(stat -c %s "$path") $index"
done | sort -k1,1nr -k2,2n)
for index in "${!cases[@]}"; do
  ((shard_of[index] == shard_index)) || continue
  read -r name path genus loops origin <<<"${cases[$index]}"
  if [[ -n "${refused[$name]:-}" ]]; then
    for command in flow param spline; do
      run "$name: $command --strict refused" 2 "$RICCI" "$command" "$path" --strict -o "$name.$command.out"
      if grep -q "${refused[$name]}" err.txt; then ok; else fail "$name: $command says why" "$(cat err.txt)"; fi
    done
  fi
  # flow
  if run "$name: flow" 0 "$RICCI" flow "$path" --json; then
    json_true "$name: flow converges" out.json 'd["converged"] and (d["max_error"] <= 1e-10 or all("floor" in x["message"] for x in d["components"]))'
  fi
  # param, on the input's own faces
  if run "$name: param" 0 "$RICCI" param "$path" -o "$name.obj" --json; then
    cp out.json "$name.param.json"
    json_true "$name: param converges" "$name.param.json" 'd["converged"]'
    if [[ ! -f "$checkuv" ]]; then
      :  # ../shared/tools missing: the independent checks are skipped (said once above)
    elif "$PYTHON" "$checkuv" "$name.obj" >"$name.check.json" 2>/dev/null; then
      flips=${allowed_flips[$name]:-0} degenerate=${allowed_degenerate[$name]:-0}
      json_true "$name: checkuv flipped <= $flips, degenerate <= $degenerate, seams exact" \
        "$name.check.json" \
        "d['flipped'] <= $flips and d['degenerate'] <= $degenerate and d['seam_length_mismatch'] <= 1e-8"
      # A flipped face turns the uv angle sums at its corners: checkuv then counts them as cones.
      cones=$("$PYTHON" -c "import json,sys; print(len(json.load(open(sys.argv[1]))['cones']))" "$name.param.json")
      json_true "$name: checkuv reads back the $cones cones" "$name.check.json" \
        "d['cones'] == $cones or d['flipped'] > 0"
      # Same vertices and faces as the input: the output's counts are the input's.
      faces=$("$RICCI" info "$path" --json 2>/dev/null | "$PYTHON" -c "import json,sys; print(json.load(sys.stdin)['faces'])")
      json_true "$name: the input's $faces faces" "$name.check.json" "d['faces'] == $faces"
    else
      fail "$name: checkuv" "could not read $name.obj"
    fi
  fi
  # sphere
  if [[ "$genus" == 0 && "$loops" == 0 ]]; then
    if run "$name: sphere" 0 "$RICCI" sphere "$path" -o "$name.sphere.obj" --json; then
      inverted=${allowed_inverted[$name]:-0}
      json_true "$name: sphere inverted <= $inverted" out.json "d['invariants']['inverted_faces'] <= $inverted"
    fi
  fi
  # hyperbolic
  if [[ "$genus" -ge 2 && "$loops" == 0 ]]; then
    if run "$name: flow --geometry hyperbolic" 0 "$RICCI" flow "$path" --geometry hyperbolic --json; then
      json_true "$name: hyperbolic flow converges" out.json 'd["converged"]'
    fi
    if run "$name: param --geometry hyperbolic" 0 "$RICCI" param "$path" --geometry hyperbolic -o "$name.disk.obj" --json; then
      if [[ "$origin" == shared || "$genus" -le 5 ]]; then
        json_true "$name: Fuchsian relation to 1e-10" out.json 'd["fuchsian_group"]["relation_residual"] <= 1e-10'
      fi
    fi
  fi
  # spline (one refinement level: the surface of a 268k-face scan has 3M faces at two)
  run "$name: spline" 0 "$RICCI" spline "$path" -o "$name.spline.obj" --refine 1 --json
done
finish
