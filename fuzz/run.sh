#!/usr/bin/env bash
# Runs each libFuzzer target for SECONDS seconds on a scratch copy of its seed corpus
# fuzz/corpus/<target>, two targets at a time (each libFuzzer process uses one core). Fails when
# any target finds a crash, a leak, a sanitizer report, a timeout or runs out of memory; the
# reproducer is left in BUILD_DIR/findings/<target>/ and the log's tail is printed.
#   fuzz/run.sh [SECONDS] [BUILD_DIR]   (defaults: 60, build-fuzz)
# BUILD_DIR build-fuzz is configured here (clang++, fuzzers only). Another BUILD_DIR must be a
# clang++ tree configured with -DRICCI_FUZZ=ON (.ci/run passes its sanitizer tree, build-asan, so
# that nothing is compiled twice); its fuzz targets are built if they are not yet.
# New inputs the fuzzers find go to BUILD_DIR/corpus/<target>: fuzz/corpus/ keeps only the
# hand-made seeds (add a finding there by hand, once fixed, as a regression seed).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
build=${2:-build-fuzz}
jobs=${RICCI_FUZZ_JOBS:-2}
targets=(read_obj read_off read_ply read_stl flow)

if [ "$build" = build-fuzz ]; then
  cmake -S . -B build-fuzz -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DRICCI_FUZZ=ON -DRICCI_BUILD_TESTS=OFF -DRICCI_BUILD_PYTHON=OFF -DRICCI_BUILD_RENDER=OFF \
    -DRICCI_BUILD_BENCH=OFF >/dev/null
elif ! grep -q '^RICCI_FUZZ:BOOL=ON' "$build/CMakeCache.txt" 2>/dev/null; then
  echo "fuzz: $build is not a build tree configured with -DRICCI_FUZZ=ON" >&2
  exit 2
fi
cmake --build "$build" -j2 --target "${targets[@]/#/fuzz_}"

export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1

# fuzz_one TARGET: one libFuzzer run; its exit status is that of the fuzzer.
fuzz_one() {
  local t=$1 work=$build/corpus/$1 findings=$build/findings/$1
  rm -rf "$work" "$findings"
  mkdir -p "$work" "$findings"
  cp fuzz/corpus/"$t"/* "$work"/
  "$build"/fuzz/fuzz_"$t" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -max_len=4096 -print_final_stats=1 -artifact_prefix="$findings/" "$work" \
    >"$build/fuzz-$t.log" 2>&1
}

echo "fuzz: ${targets[*]} for ${seconds} s each, $jobs at a time"
declare -A pid_target=()
failed=()
collect() {  # waits for one fuzzer to end and records whether it failed
  local pid status
  wait -n -p pid "${!pid_target[@]}" && status=0 || status=$?
  [ "$status" -ne 0 ] && failed+=("${pid_target[$pid]}")
  unset "pid_target[$pid]"
}
for t in "${targets[@]}"; do
  while [ ${#pid_target[@]} -ge "$jobs" ]; do collect; done
  fuzz_one "$t" &
  pid_target[$!]=$t
done
while [ ${#pid_target[@]} -gt 0 ]; do collect; done

for t in "${targets[@]}"; do
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$build/fuzz-$t.log")
  added=$(sed -n 's/^stat::new_units_added: *//p' "$build/fuzz-$t.log")
  echo "fuzz: $t: ${runs:-?} executions, ${added:-?} new inputs (kept in $build/corpus/$t)"
done
for t in "${failed[@]}"; do
  tail -n 60 "$build/fuzz-$t.log"
  echo "fuzz: $t FAILED; reproducer(s) in $build/findings/$t: $(ls "$build/findings/$t")"
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz: findings in ${failed[*]}" >&2
  exit 1
fi
echo "fuzz: no findings"
