# Shared by the command-line test scripts (sourced, not run): checks RICCI, makes a scratch
# folder, counts checks, and prints the closing "N passed, M failed" line.
#   source check_framework.sh NAME [SCRATCH_DIR]
# sets PYTHON and WORK (the current folder afterwards), defines ok, fail and finish.

if [[ -z "${RICCI:-}" || ! -x "${RICCI}" ]]; then
  echo "$1: set RICCI to the ricci executable (got '${RICCI:-}')" >&2
  exit 2
fi
PYTHON=/usr/bin/python3
[[ -x "$PYTHON" ]] || PYTHON=python3

scratch="${2:-${TMPDIR:-/tmp}}"
mkdir -p "$scratch" || exit 2
WORK="$(mktemp -d "$scratch/$1.XXXXXX")" || exit 2
cd "$WORK" || exit 2

passed=0
failed=0
ok() { passed=$((passed + 1)); }
fail() {  # fail NAME REASON
  failed=$((failed + 1))
  echo "FAIL: $1: $2"
}

# finish: the summary line; exits 1 (keeping WORK) when a check failed, else removes WORK.
finish() {
  echo "$passed passed, $failed failed"
  if ((failed > 0)); then
    echo "scratch files kept in $WORK" >&2
    exit 1
  fi
  cd / && rm -rf "$WORK"
  exit 0
}
