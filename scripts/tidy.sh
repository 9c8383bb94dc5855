#!/usr/bin/env bash
# clang-tidy (.clang-tidy) over the library's, the command line's, the Python module's and the
# tests' sources, with a build's compile_commands.json (every configuration writes one; python/src
# and tests need a configuration that builds them, the default).
#
#   scripts/tidy.sh BUILD_DIR BASE    # the .cpp files under src/, apps/, python/src/ and tests/
#                                     # changed since BASE
#   scripts/tidy.sh BUILD_DIR --all   # all of them
#
# CI lints what the newest commit changed (BASE = HEAD~1): the whole tree (160 files) takes about
# 1200 s of CPU (7.5 s a file: parsing Eigen dominates, not the checks), more than CI's budget; run
# --all before a release or after changing .clang-tidy. Findings are errors (WarningsAsErrors);
# the exit status is non-zero when any file has one.
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:?usage: scripts/tidy.sh BUILD_DIR BASE|--all}"
base="${2:?usage: scripts/tidy.sh BUILD_DIR BASE|--all}"
if [ ! -f "$build/compile_commands.json" ]; then
  echo "tidy: $build/compile_commands.json not found (configure the build first)" >&2
  exit 2
fi
# A unity build's database names its batches, not the files: configure (only) a tree beside it
# with the same compiler, type and flags, file by file, and lint with that one's database.
if grep -q '"file": "[^"]*/Unity/unity_' "$build/compile_commands.json"; then
  cache() { sed -n "s/^$1:[A-Z]*=//p" "$build/CMakeCache.txt"; }
  cmake -S . -B "$build/tidy-db" -DRICCI_UNITY_BUILD=OFF -DCMAKE_EXPORT_COMPILE_COMMANDS=ON \
    -DCMAKE_CXX_COMPILER="$(cache CMAKE_CXX_COMPILER)" -DCMAKE_BUILD_TYPE="$(cache CMAKE_BUILD_TYPE)" \
    -DCMAKE_CXX_FLAGS="$(cache CMAKE_CXX_FLAGS)" >/dev/null
  build="$build/tidy-db"
fi
# Each folder whose files the build compiled (a build without the Python module or the tests has
# no flags for them).
sources=('src/*.cpp' 'apps/*.cpp')
for folder in python/src tests; do
  if grep -q "\"file\": \"[^\"]*/$folder/" "$build/compile_commands.json"; then
    sources+=("$folder/*.cpp")
  else
    echo "tidy: $build does not compile $folder; not linted" >&2
  fi
done
if [ "$base" = "--all" ]; then
  mapfile -t files < <(git ls-files "${sources[@]}")
else
  mapfile -t files < <(git diff --name-only --diff-filter=d "$base" HEAD -- "${sources[@]}")
fi
if [ "${#files[@]}" -eq 0 ]; then
  echo "tidy: no C++ source changed since $base"
  exit 0
fi
echo "tidy: ${#files[@]} file(s)"
start=$SECONDS
status=0
# (-Wno-unknown-warning-option: a g++ build's flags such as -Wno-restrict are unknown to clang,
# and CI's -Werror would make them errors.)
printf '%s\n' "${files[@]}" |
  xargs -P 2 -n 1 clang-tidy -p "$build" --quiet --extra-arg=-Wno-unknown-warning-option \
    2>/dev/null || status=$?
echo "tidy: ${#files[@]} file(s) in $((SECONDS - start)) s"
exit "$status"
