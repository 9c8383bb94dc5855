#!/usr/bin/env bash
# clang-tidy (.clang-tidy) over the library's and the command line's sources, with a build's
# compile_commands.json (every configuration writes one).
#
#   scripts/tidy.sh BUILD_DIR BASE    # the .cpp files under src/ and apps/ changed since BASE
#   scripts/tidy.sh BUILD_DIR --all   # all of them
#
# CI lints what the newest commit changed (BASE = HEAD~1): the whole tree takes about 680 s of
# CPU (7.7 s a file: parsing Eigen dominates, not the checks), more than CI's budget leaves; run
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
if [ "$base" = "--all" ]; then
  mapfile -t files < <(git ls-files 'src/*.cpp' 'apps/*.cpp')
else
  mapfile -t files < <(git diff --name-only --diff-filter=d "$base" HEAD -- 'src/*.cpp' 'apps/*.cpp')
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
