#!/usr/bin/env bash
# Wall time of `ricci param MESH --cones N` against BFF's `bff-command-line IN OUT --nCones=N`
# (built outside the project; RICCI_BFF names it) at the same N, on every mesh of
# ../shared/reference/bff-cones.tsv (N = 4, 8, 16, 32) and on a generated 1M-face disk
# (`ricci generate disk --resolution 408`, 8 cones). Each pair runs back to back, RUNS times
# (default 1; the disk 3), the median taken; ratio = ricci / BFF. BFF reads OBJ only: other
# formats are converted once (`ricci param` reads the same file either way: the converted OBJ
# keeps positions and faces in order). Without RICCI_BFF only ricci's times are printed.
#
#   RICCI_BFF=/path/to/bff-command-line bench/speed.sh [BUILD_DIR] [OUT_DIR]
#   RICCI_SPEED_MESHES="spot kitten" ...    only these meshes;  RICCI_SPEED_DISK=0: no disk
#   RICCI_SPEED_FREE=0                       no `--seams free` column
#
# Prints a markdown table (mesh, N, ricci s, BFF s, ratio) and the median ratio. On a surface of
# genus >= 1 (the shared MANIFEST.tsv's genus column) BFF's output is a map with free seams, not a
# flat metric with N cones (docs/cones.md): those rows also time `--seams free`, the map of BFF's
# own kind (free s, free ratio = free s / BFF s), with a median of their own.
set -uo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=bench/lib.sh
source bench/lib.sh
bench_paths speed "$@"
mkdir -p "$out"
reference=$PWD/../shared/reference/bff-cones.tsv
bff=${RICCI_BFF:-}
runs=${RICCI_SPEED_RUNS:-1}
only=" ${RICCI_SPEED_MESHES:-} "

now() { date +%s.%N; }
# median of the wall seconds of RUNS runs of a command (stdout and stderr dropped)
timed() {
  local runs=$1 i s e
  shift
  for ((i = 0; i < runs; ++i)); do
    s=$(now)
    "$@" >/dev/null 2>&1
    e=$(now)
    echo "$e - $s" | bc
  done | sort -n | awk '{a[NR]=$1} END {printf "%.3f", a[int((NR+1)/2)]}'
}
obj_of() {  # a mesh file -> an OBJ with the same vertices and faces (converted once)
  local f=$1 name
  name=$(basename "${f%.*}")
  case "$f" in
    *.obj) echo "$f" ;;
    *)
      [ -f "$out/$name.obj" ] || /usr/bin/python3 - "$f" "$out/$name.obj" "$PWD/$build/python" <<'PY'
import sys
sys.path.insert(0, sys.argv[3])
import ricci
V, F, _ = ricci.read_mesh(sys.argv[1])
ricci.write_obj(sys.argv[2], V, F)
PY
      echo "$out/$name.obj"
      ;;
  esac
}

echo "| mesh | cones | ricci s | BFF s | ratio | free s | free ratio |"
echo "|---|---|---|---|---|---|---|"
ratios=()
free_ratios=()
manifest=$shared/MANIFEST.tsv
genus_of() {  # mesh name -> its genus in the manifest (empty when unknown)
  [ -f "$manifest" ] || return 0
  awk -F'\t' -v n="$1" 'NR == 1 {for (i = 1; i <= NF; ++i) if ($i == "genus") g = i; next}
    {f = $1; sub(/\.[^.]*$/, "", f)} f == n && g {print $g}' "$manifest"
}
row() {  # name file n
  local name=$1 file=$2 n=$3 r b obj f="-" free_ratio="-" genus
  r=$(timed "$runs" "$ricci" param "$file" --cones "$n" --texture none -o "$out/$name-$n.obj")
  genus=$(genus_of "$name")
  if [ "${RICCI_SPEED_FREE:-1}" != 0 ] && [[ "$genus" =~ ^[0-9]+$ ]] && [ "$genus" -ge 1 ]; then
    f=$(timed "$runs" "$ricci" param "$file" --cones "$n" --seams free --texture none \
      -o "$out/$name-$n-free.obj")
  fi
  if [ -n "$bff" ]; then
    obj=$(obj_of "$file")
    b=$(timed "$runs" "$bff" "$obj" "$out/$name-$n-bff.obj" "--nCones=$n")
    ratio=$(echo "scale=3; $r / $b" | bc)
    ratios+=("$ratio")
    if [ "$f" != "-" ]; then
      free_ratio=$(echo "scale=3; $f / $b" | bc)
      free_ratios+=("$free_ratio")
    fi
    echo "| $name | $n | $r | $b | $ratio | $f | $free_ratio |"
  else
    echo "| $name | $n | $r | - | - | $f | - |"
  fi
}
# One untimed run of each tool first: the first row otherwise pays for cold caches (spot with 4
# cones took 68-89 ms in the table, 36-40 ms in runs after others; BFF 0.13 s against 0.06 s).
warm_up=$(ls "$shared"/spot.* 2>/dev/null | head -1)
if [ -n "$warm_up" ]; then
  "$ricci" param "$warm_up" --cones 4 --texture none -o "$out/warm-up.obj" >/dev/null 2>&1
  [ -n "$bff" ] && "$bff" "$(obj_of "$warm_up")" "$out/warm-up-bff.obj" --nCones=4 >/dev/null 2>&1
fi
if [ -f "$reference" ] && [ -d "$shared" ]; then
  while IFS=$'\t' read -r name n _; do
    [[ "$name" == \#* || "$name" == mesh ]] && continue
    [[ "$only" == "  " || "$only" == *" $name "* ]] || continue
    file=$(ls "$shared/$name".* 2>/dev/null | head -1)
    [ -n "$file" ] && row "$name" "$file" "$n"
  done < <(awk -F'\t' '{print $1 "\t" $2}' "$reference")
else
  echo "note: $reference or $shared missing: the disk only" >&2
fi
if [ "${RICCI_SPEED_DISK:-1}" != 0 ]; then
  disk=$out/disk1m.obj
  [ -f "$disk" ] || "$ricci" generate disk --resolution 408 -o "$disk" >/dev/null
  runs_saved=$runs
  runs=${RICCI_SPEED_DISK_RUNS:-3}
  row disk1m "$disk" 8
  runs=$runs_saved
fi
if [ ${#ratios[@]} -gt 0 ]; then
  printf '%s\n' "${ratios[@]}" | sort -n | awk '{a[NR]=$1} END {printf "\nmedian ratio %.2f over %d rows; rows at most 0.5: %d\n", a[int((NR+1)/2)], NR, c} $1 <= 0.5 {c++}'
fi
if [ ${#free_ratios[@]} -gt 0 ]; then
  printf '%s\n' "${free_ratios[@]}" | sort -n | awk '{a[NR]=$1} END {printf "--seams free on genus >= 1: median ratio %.2f over %d rows; rows at most 0.5: %d\n", a[int((NR+1)/2)], NR, c} $1 <= 0.5 {c++}'
fi
