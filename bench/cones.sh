#!/usr/bin/env bash
# Automatic cones against BFF: for every row of ../shared/reference/bff-cones.tsv (a shared mesh
# and a cone count), `ricci param MESH --cones N` with default options, then the same with
# --quantize, and `--cones auto`; ../shared/tools/checkuv.py measures each written OBJ (area
# distortion E of the tutorial's eq. 9, log-area rms, angle distortion, flipped faces, seam
# mismatch, cones). BFF's figures come from the TSV (same checker, same meshes).
# RICCI_CEPS=PATH (CEPS's parameterize binary, built outside the project) adds the exact peer at
# its own cone count on the genus >= 1 meshes.
# bench/bff-checker.tsv (bench/bff-checker.sh, with BFF built outside the project) says where
# BFF's output is not a flat metric with N cones: curvature on other vertices, along its seams.
# For those rows the fewest exact cones of ours that beat BFF's figures are searched (N, 2N, ...
# up to as many as BFF's output has curved vertices) and listed in a second table.
#
#   bench/cones.sh [BUILD_DIR] [OUT_DIR]         (defaults: build, build/cones)
#   RICCI_CONES_MESHES="spot bunny" bench/cones.sh    only these meshes
#
# Prints a markdown table on stdout (the one in docs/cones.md); the outputs stay in OUT_DIR,
# with every checker's JSON in OUT_DIR/rows.tsv.
set -uo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=bench/lib.sh
source bench/lib.sh
bench_paths cones "$@"
reference=$PWD/../shared/reference/bff-cones.tsv
mkdir -p "$out"
if [ ! -f "$reference" ] || [ ! -d "$shared" ]; then
  echo "cones.sh: needs $reference and $shared" >&2
  exit 0
fi
only=" ${RICCI_CONES_MESHES:-} "

path_of() {  # mesh name -> file under shared/meshes
  local f
  for f in "$shared/$1".*; do
    [ -f "$f" ] && echo "$f" && return
  done
}
# field of the checker's JSON
field() { /usr/bin/python3 -c "import json,sys; d=json.load(open(sys.argv[1])); v=d.get(sys.argv[2]); print('%.5g' % v if isinstance(v, float) else v)" "$1" "$2" 2>/dev/null; }
report() { /usr/bin/python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print($2)" "$1" 2>/dev/null; }

# runs ricci param, the checker; sets e, angle, flipped, mismatch, ncones, seconds, select, ok
measure() {  # name, tag, extra args...
  local name=$1 tag=$2 start end
  shift 2
  local obj="$out/$name-$tag.obj"
  start=$(date +%s.%N)
  "$ricci" param "$(path_of "$name")" -o "$obj" --report "$out/$name-$tag.json" "$@" \
    >"$out/$name-$tag.log" 2>&1
  local rc=$?
  end=$(date +%s.%N)
  seconds=$(printf '%.2f' "$(echo "$end - $start" | bc)")
  e=- angle=- flipped=- mismatch=- ncones=- select=- log_rms=-
  [ $rc -eq 0 ] || { ok="exit $rc"; return; }
  ok=ok
  /usr/bin/python3 "$checkuv" "$obj" >"$out/$name-$tag.check.json"
  e=$(field "$out/$name-$tag.check.json" area_distortion_energy)
  log_rms=$(field "$out/$name-$tag.check.json" log_area_rms)
  angle=$(field "$out/$name-$tag.check.json" angle_distortion_mean)
  flipped=$(field "$out/$name-$tag.check.json" flipped)
  mismatch=$(field "$out/$name-$tag.check.json" seam_length_mismatch)
  ncones=$(field "$out/$name-$tag.check.json" cones)
  select=$(report "$out/$name-$tag.json" '"%.2f" % d["timings"]["cones"]')
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$tag" "$ncones" "$e" "$log_rms" \
    "$angle" "$flipped" "$mismatch" "$seconds" "$select" >>"$out/rows.tsv"
}

bff_checker=$PWD/bench/bff-checker.tsv
# BFF's curvature away from its N strongest cones: "vertices sum_over_pi", or nothing.
off_cones() { [ -f "$bff_checker" ] && awk -F'\t' -v m="$1" -v n="$2" '$1 == m && $2 == n {print $4, $5}' "$bff_checker"; }
# the figures of an earlier measure of (name, tag), from rows.tsv
lookup() {
  local line
  line=$(awk -F'\t' -v m="$1" -v t="$2" '$1 == m && $2 == t' "$out/rows.tsv" | tail -1)
  [ -n "$line" ] || return 1
  IFS=$'\t' read -r _ _ ncones e log_rms angle flipped mismatch seconds select <<<"$line"
}

printf 'mesh\trun\tcones\tE\tlog_area_rms\tangle_mean\tflipped\tseam_mismatch\tseconds\tselect_seconds\n' >"$out/rows.tsv"
# yes when ricci has lower E, no more angle distortion, no flipped face and exact seams
beats() { /usr/bin/python3 -c "import sys; e,be,a,ba,f,m=sys.argv[1:]; print('yes' if float(e)<float(be) and float(a)<=float(ba) and int(f)==0 and float(m)<=1e-9 else 'no')" "$@" 2>/dev/null || echo no; }
wins=0 rows=0
echo "| mesh | cones | BFF E | ricci E | BFF angle | ricci angle | ricci flipped | ricci seam mismatch | beats BFF | BFF curved vertices off its N cones | ricci log-area rms | ricci s (selection) | BFF s | ricci --quantize: E, angle, flipped |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
while IFS=$'\t' read -r name n bff_s bff_e bff_angle bff_flipped; do
  case "$name" in '#'*|mesh|'') continue ;; esac
  [ "$only" = "  " ] || [[ "$only" == *" $name "* ]] || continue
  [ -n "$(path_of "$name")" ] || continue
  measure "$name" "$n" --cones "$n"
  verdict=$(beats "$e" "$bff_e" "$angle" "$bff_angle" "$flipped" "$mismatch")
  rows=$((rows + 1))
  [ "$verdict" = yes ] && wins=$((wins + 1))
  read -r off_vertices off_sum <<<"$(off_cones "$name" "$n")"
  off="${off_vertices:--}"
  [ "${off_vertices:-0}" -gt 0 ] && off="$off_vertices (${off_sum} pi)"
  row="| $name | $n | $bff_e | $e | $bff_angle | $angle | $flipped | $mismatch | $verdict | $off | $log_rms | $seconds ($select) | $bff_s"
  [ "$ok" = ok ] || row="$row ($ok)"
  measure "$name" "$n-q" --cones "$n" --quantize
  echo "$row | $e, $angle, $flipped |"
done <"$reference"
echo
echo "ricci beats BFF (lower E, no more angle distortion, no flipped face, seams within 1e-9) on $wins of $rows rows."

# Seams that may bend (--seams free) on the rows where BFF's output carries curvature along its
# cut (genus >= 1): a map of BFF's own kind at BFF's N.
if [ -f "$bff_checker" ]; then
  echo
  echo "--seams free (cones and cut chosen for bending seams, one length per seam edge) on the rows"
  echo "where BFF's seams carry curvature:"
  echo
  echo "| mesh | cones | BFF E | ricci free E | BFF angle | ricci free angle | flipped | seam mismatch | beats BFF | seam curvature max | ricci s (seams) | BFF s |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
  free_rows=0 free_wins=0
  while IFS=$'\t' read -r name n _ off_vertices _ _ bff_e bff_angle _; do
    [ "$name" = mesh ] && continue
    [ "$only" = "  " ] || [[ "$only" == *" $name "* ]] || continue
    [ -n "$(path_of "$name")" ] && [ "$off_vertices" -gt 0 ] || continue
    bff_s=$(awk -F'\t' -v m="$name" -v c="$n" '$1 == m && $2 == c {print $3}' "$reference")
    measure "$name" "$n-free" --cones "$n" --seams free
    verdict=$(beats "$e" "$bff_e" "$angle" "$bff_angle" "$flipped" "$mismatch")
    free_rows=$((free_rows + 1))
    [ "$verdict" = yes ] && free_wins=$((free_wins + 1))
    seams=$(report "$out/$name-$n-free.json" '"%.3g (%.2f)" % (d["seams"]["curvature_max"], d["seams"]["choice_seconds"])')
    echo "| $name | $n | $bff_e | $e | $bff_angle | $angle | $flipped | $mismatch | $verdict | ${seams% *} | $seconds ${seams#* } | $bff_s |"
  done <"$bff_checker"
  echo
  echo "--seams free beats BFF on $free_wins of $free_rows rows."
fi

# The exact peer: CEPS (built outside the project; RICCI_CEPS names its `parameterize` binary)
# with its default greedy cones on every mesh of genus >= 1, against ours with rigid seams at
# CEPS's own count (and --seams free at that count for reference).
ceps=${RICCI_CEPS:-}
if [ -n "$ceps" ] && [ -x "$ceps" ] && [ -f "$bff_checker" ]; then
  echo
  echo "Exact maps at CEPS's own cone count (CEPS: default greedy cones, its linear texture on"
  echo "the common refinement):"
  echo
  echo "| mesh | CEPS cones | CEPS E | ricci E | CEPS angle | ricci angle | ricci flipped | ricci route | CEPS s | ricci s | ricci --seams free E |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|"
  for name in $(awk -F'\t' '$1 != "mesh" && $4 > 0 {print $1}' "$bff_checker" | uniq); do
    [ "$only" = "  " ] || [[ "$only" == *" $name "* ]] || continue
    input=$(path_of "$name")
    [ -n "$input" ] || continue
    obj="$out/$name-ceps-input.obj"
    case "$input" in
      *.off) awk 'NR == 1 {next} NR == 2 {nv = $1; next} nv > 0 {print "v", $1, $2, $3; nv--; next}
                  NF >= 4 {print "f", $2 + 1, $3 + 1, $4 + 1}' "$input" >"$obj" ;;
      *) cp "$input" "$obj" ;;
    esac
    start=$(date +%s.%N)
    "$ceps" "$obj" --outputLinearTextureFilename="$out/$name-ceps.obj" >"$out/$name-ceps.log" 2>&1
    ceps_s=$(printf '%.2f' "$(echo "$(date +%s.%N) - $start" | bc)")
    /usr/bin/python3 "$checkuv" "$out/$name-ceps.obj" >"$out/$name-ceps.check.json"
    # CEPS's cones: interior vertices whose uv angle sum is off 2 pi by more than 0.01 (a stock
    # CEPS writes 6 digits, so the checker's 1e-6 counts rounding, and it lists only the 50
    # smallest sums: point RICCI_CEPS at a build whose OBJ writer keeps 17 digits).
    n=$(report "$out/$name-ceps.check.json" 'sum(1 for a in d["cone_angle_sums_over_pi"] if abs(a - 2) > 0.01 / 3.14159)')
    ceps_e=$(field "$out/$name-ceps.check.json" area_distortion_energy)
    ceps_angle=$(field "$out/$name-ceps.check.json" angle_distortion_mean)
    measure "$name" "$n-ceps" --cones "$n"
    route=$(report "$out/$name-$n-ceps.json" '",".join(r["method"] for r in d["routes"])')
    row="| $name | $n | $ceps_e | $e | $ceps_angle | $angle | $flipped | $route | $ceps_s | $seconds"
    measure "$name" "$n-ceps-free" --cones "$n" --seams free
    echo "$row | $e |"
  done
fi

if [ -f "$bff_checker" ]; then
  echo
  echo "Rows where BFF's output is not a flat metric with N cones (bench/bff-checker.tsv: interior"
  echo "vertices off its N strongest cones with |2 pi - angle sum| > 1e-3), and the fewest exact"
  echo "cones of ours (N, 2N, ... up to as many as BFF has curved vertices) that beat its figures:"
  echo
  echo "| mesh | BFF cones | BFF curved vertices off them (their curvature) | BFF seam mismatch | BFF E, angle | fewest ricci cones that beat it | ricci E, angle, flipped, seam mismatch |"
  echo "|---|---|---|---|---|---|---|"
  curved=0 beaten=0
  while IFS=$'\t' read -r name n _ off_vertices off_sum bff_mismatch bff_e bff_angle _; do
    [ "$name" = mesh ] && continue
    [ "$only" = "  " ] || [[ "$only" == *" $name "* ]] || continue
    [ -n "$(path_of "$name")" ] && [ "$off_vertices" -gt 0 ] || continue
    curved=$((curved + 1))
    # Up to as many cones as BFF's output has curved vertices (its N and the others).
    limit=$((n + off_vertices))
    found="none up to $limit" figures=-
    m=$n
    while [ "$m" -le "$limit" ]; do
      lookup "$name" "$m" ||
        { measure "$name" "$m" --cones "$m" --max-cones "$m"; lookup "$name" "$m"; }
      if [ "$(beats "$e" "$bff_e" "$angle" "$bff_angle" "$flipped" "$mismatch")" = yes ]; then
        found=$m figures="$e, $angle, $flipped, $mismatch"
        beaten=$((beaten + 1))
        break
      fi
      # Doubling, and BFF's own count last.
      if [ "$m" -lt "$limit" ] && [ $((2 * m)) -gt "$limit" ]; then m=$limit; else m=$((2 * m)); fi
    done
    echo "| $name | $n | $off_vertices ($off_sum pi) | $bff_mismatch | $bff_e, $bff_angle | $found | $figures |"
  done <"$bff_checker"
  echo
  echo "Of the $curved rows whose BFF output carries curvature off its N cones, ricci beats $beaten with at most as many exact cones as BFF has curved vertices (its N and the others)."
fi

echo
echo "| mesh | --cones auto: cones | E | angle | flipped | log-area rms | s (selection) |"
echo "|---|---|---|---|---|---|---|"
for name in $(awk -F'\t' '!/^#/ && $1 != "mesh" {print $1}' "$reference" | uniq); do
  [ "$only" = "  " ] || [[ "$only" == *" $name "* ]] || continue
  [ -n "$(path_of "$name")" ] || continue
  measure "$name" auto --cones auto
  echo "| $name | $ncones | $e | $angle | $flipped | $log_rms | $seconds ($select) |"
done
