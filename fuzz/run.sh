#!/usr/bin/env bash
# Builds the libFuzzer targets in build-fuzz (clang++) and runs each for SECONDS seconds on a copy
# of its seed corpus in fuzz/corpus/<target>. Fails when any target finds a crash, a leak, a
# sanitizer report or a timeout; the reproducer is left in build-fuzz/findings/<target>/.
#   fuzz/run.sh [SECONDS]   (default 60)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
targets=(read_obj read_off read_ply read_stl flow)

cmake -S . -B build-fuzz -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DRICCI_FUZZ=ON -DRICCI_BUILD_TESTS=OFF -DRICCI_BUILD_PYTHON=OFF -DRICCI_BUILD_RENDER=OFF \
  -DRICCI_BUILD_BENCH=OFF >/dev/null
cmake --build build-fuzz -j2 --target "${targets[@]/#/fuzz_}"

export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
failed=()
for t in "${targets[@]}"; do
  work=build-fuzz/corpus/$t findings=build-fuzz/findings/$t
  rm -rf "$work" "$findings"
  mkdir -p "$work" "$findings"
  cp fuzz/corpus/"$t"/* "$work"/
  echo "fuzz: $t for ${seconds}s"
  # New inputs go to the scratch corpus; fuzz/corpus/ keeps only the hand-made seeds.
  if ! build-fuzz/fuzz/fuzz_"$t" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -max_len=4096 -print_final_stats=1 -artifact_prefix="$findings/" "$work" \
    >build-fuzz/fuzz-"$t".log 2>&1; then
    failed+=("$t")
    tail -n 60 build-fuzz/fuzz-"$t".log
    echo "fuzz: $t FAILED; reproducer(s): $(ls "$findings")"
  fi
  grep -E '^stat::number_of_executed_units|^stat::new_units_added' build-fuzz/fuzz-"$t".log |
    sed "s/^/fuzz: $t /" || true
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz: findings in ${failed[*]}" >&2
  exit 1
fi
echo "fuzz: no findings"
