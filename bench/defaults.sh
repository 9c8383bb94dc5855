#!/usr/bin/env bash
# Every command with default options on every manifold mesh of ../shared/meshes and on generated
# hard cases (CAD strips and fans, valence-3 vertices, 0.1-degree needles, high genus, hundreds of
# holes): one row per run with seconds, exit code, flips, reached error, and for param the
# distortion and flipped faces that ../shared/tools/checkuv.py measures on the written OBJ.
#
#   bench/defaults.sh [BUILD_DIR] [OUT_DIR]      (defaults: build, build/defaults)
#
# Prints a markdown table on stdout; the outputs stay in OUT_DIR.
set -uo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=bench/lib.sh
source bench/lib.sh
bench_paths defaults "$@"
mkdir -p "$out/generated"

# name path genus boundary_loops (genus -1: not a manifold)
cases=()
if [ -f "$shared/MANIFEST.tsv" ]; then
  while IFS=$'\t' read -r file _ _ _ _ _ _ loops _ genus manifold _; do
    [ "$manifold" = "yes" ] || continue
    case "$genus" in ''|*[!0-9]*) continue ;; esac
    cases+=("${file%.*} $shared/$file $genus $loops")
  done < <(tail -n +2 "$shared/MANIFEST.tsv")
fi
gen() {  # name, genus, loops, generate arguments...
  local name=$1 genus=$2 loops=$3
  shift 3
  "$ricci" generate "$@" -o "$out/generated/$name.obj" >/dev/null && cases+=("$name $out/generated/$name.obj $genus $loops")
}
gen cad-cylinder 0 0 cad-cylinder
gen cad-ring 1 0 cad-ring
gen valence3-sphere 0 0 icosphere --resolution 5 --valence3
gen needles-genus2 2 0 surface --genus 2 --resolution 40 --needles 0.998
gen needles-sphere-82k 0 0 icosphere --resolution 6 --needles 0.998
gen genus-20 20 0 surface --genus 20 --resolution 41
gen genus-50 50 0 surface --genus 50 --resolution 101
gen genus-150 150 0 surface --genus 150 --resolution 301
gen holes-300 0 300 surface --genus 0 --holes 300 --resolution 60
[ -n "${RICCI_BIG:-}" ] && gen scan-800k-250-holes 40 250 surface --genus 40 --holes 250 --resolution 1950 --needles 0.9

json() { /usr/bin/python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print($2)" "$3" 2>/dev/null; }
run() {  # command name: runs, sets rc and seconds
  local start end
  start=$(date +%s.%N)
  "$@" >"$out/last.json" 2>"$out/last.err"
  rc=$?
  end=$(date +%s.%N)
  seconds=$(echo "$end - $start" | bc)
}

echo "| mesh | command | exit | seconds | flips | reached error | distortion (checkuv: E, angle mean, flipped, degenerate) | note |"
echo "|---|---|---|---|---|---|---|---|"
for c in "${cases[@]}"; do
  read -r name path genus loops <<<"$c"
  run "$ricci" flow "$path" --json
  flips=$(json "" "d[\"flipped_edges\"]" "$out/last.json")
  err=$(json '' '"%.2e" % d["max_error"]' "$out/last.json")
  printf '| %s | flow | %s | %.2f | %s | %s | | %s |\n' "$name" "$rc" "$seconds" "$flips" "$err" "$(head -c 120 "$out/last.err" | tr '\n|' '  ')"
  run "$ricci" param "$path" -o "$out/$name.obj" --json
  flips=$(json '' 'd["flow"]["flipped_edges"]' "$out/last.json")
  err=$(json '' '"%.2e" % d["flow"]["max_error"]' "$out/last.json")
  cones=$(json '' 'len(d["cones"])' "$out/last.json")
  q=$(/usr/bin/python3 "$checkuv" "$out/$name.obj" 2>/dev/null | /usr/bin/python3 -c "import json,sys; d=json.load(sys.stdin); print('E %.3g, %.4f, %d flipped, %d degenerate' % (d['area_distortion_energy'], d['angle_distortion_mean'], d['flipped'], d['degenerate']))" 2>/dev/null)
  printf '| %s | param | %s | %.2f | %s | %s | %s | %s cones |\n' "$name" "$rc" "$seconds" "$flips" "$err" "$q" "$cones"
  if [ "$genus" = "0" ] && [ "$loops" = "0" ]; then
    run "$ricci" sphere "$path" -o "$out/$name.sphere.obj" --json
    flips=$(json '' 'd["flow"]["flipped_edges"]' "$out/last.json")
    err=$(json '' '"%.2e" % d["flow"]["max_error"]' "$out/last.json")
    inv=$(json '' '"%d inverted, angle mean %.4f" % (d["invariants"]["inverted_faces"], d["distortion"]["angle_distortion_mean"])' "$out/last.json")
    printf '| %s | sphere | %s | %.2f | %s | %s | %s | %s |\n' "$name" "$rc" "$seconds" "$flips" "$err" "$inv" "$(head -c 120 "$out/last.err" | tr '\n|' '  ')"
  fi
  if [ "$genus" != "0" ] || [ "$loops" != "0" ]; then :; fi
  if [ "$genus" -ge 2 ] && [ "$loops" = "0" ]; then
    run "$ricci" flow "$path" --geometry hyperbolic --json
    flips=$(json "" "d[\"flipped_edges\"]" "$out/last.json")
    err=$(json '' '"%.2e" % d["max_error"]' "$out/last.json")
    printf '| %s | flow --geometry hyperbolic | %s | %.2f | %s | %s | | |\n' "$name" "$rc" "$seconds" "$flips" "$err"
    run "$ricci" param "$path" --geometry hyperbolic -o "$out/$name.disk.obj" --json
    rel=$(json '' '"relation %.1e" % d["fuchsian_group"]["relation_residual"] if "fuchsian_group" in d else "group: " + d.get("fuchsian_group_failure","")[:60]' "$out/last.json")
    printf '| %s | param --geometry hyperbolic | %s | %.2f | | | %s | |\n' "$name" "$rc" "$seconds" "$rel"
  fi
  if [ "$(wc -l <"$path" 2>/dev/null || echo 0)" -lt 400000 ]; then
    run "$ricci" spline "$path" -o "$out/$name.spline.obj" --json
    e=$(json '' '"distance max %.1e" % d["error"]["max_distance"]' "$out/last.json")
    printf '| %s | spline | %s | %.2f | | | %s | %s |\n' "$name" "$rc" "$seconds" "$e" "$(head -c 120 "$out/last.err" | tr '\n|' '  ')"
  fi
done
