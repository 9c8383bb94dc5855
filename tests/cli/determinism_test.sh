#!/usr/bin/env bash
# Determinism of the `ricci` program: the same input and options give bit-identical outputs
# across runs and across BLAS thread counts. Each case runs twice with one BLAS thread and twice
# with two (OPENBLAS_NUM_THREADS and OMP_NUM_THREADS); every run must equal the first.
#
# Across thread counts this holds because src/numerics/sparse_cholesky.cpp holds OpenBLAS at one
# thread while CHOLMOD's supernodal factorisation and solves run: OpenBLAS's threaded kernels sum
# in an order that depends on the thread count (before the pinning, 1 and 2 threads gave the same
# iteration counts but u differing by ~1e-14, curvatures by ~5e-15 and uv and seam transitions by
# ~1e-13, and a transition rotation of 180 degrees could print as -180). OMP_NUM_THREADS alone
# changes nothing. A threaded BLAS other than OpenBLAS (BLIS, MKL) is not pinned: there this test
# fails.
#
# JSON outputs are compared after removing their timing fields (keys named *seconds* and
# `timings`), OBJ outputs byte for byte.
#
# Usage: RICCI=/path/to/ricci bash tests/cli/determinism_test.sh [SCRATCH_DIR]
# Needs bash, coreutils and /usr/bin/python3. Prints one line per failed check and finally
# "N passed, M failed"; exits 1 when a check failed. The working folder under SCRATCH_DIR is
# removed when every check passed and kept for inspection otherwise.
set -u

# shellcheck source=check_framework.sh
source "$(dirname "${BASH_SOURCE[0]}")/check_framework.sh" determinism "${1:-}"

# canonical FILE: FILE's bytes (OBJ), or its JSON without timing fields, keys sorted (JSON).
canonical() {
  case "$1" in
    *.json)
      "$PYTHON" - "$1" <<'EOF'
import json, sys
def strip(x):
    if isinstance(x, dict):
        return {k: strip(v) for k, v in x.items() if "seconds" not in k and k != "timings"}
    if isinstance(x, list):
        return [strip(v) for v in x]
    return x
with open(sys.argv[1]) as f:
    data = json.load(f)
# repr of every float keeps all 17 significant digits: equal text means bit-identical values.
sys.stdout.write(json.dumps(strip(data), sort_keys=True, indent=1))
EOF
      ;;
    *) cat "$1" ;;
  esac
}

# check_case NAME OUTPUTS... -- ARGS...: runs `ricci ARGS` four times (BLAS threads 1, 1, 2, 2)
# in folders run1..run4; every OUTPUT (a file name the ARGS write in the current folder) of runs
# 2, 3 and 4 must be identical, timings aside, to run 1's.
check_case() {
  local name="$1" outputs=() run threads out code
  shift
  while [[ "$1" != "--" ]]; do outputs+=("$1"); shift; done
  shift
  for run in 1 2 3 4; do
    threads=$(((run + 1) / 2))
    mkdir -p "$name/run$run"
    (cd "$name/run$run" && OPENBLAS_NUM_THREADS=$threads OMP_NUM_THREADS=$threads \
      "$RICCI" "$@" >stdout.txt 2>stderr.txt)
    code=$?
    if [[ "$code" != 0 ]]; then
      fail "$name" "run $run (threads $threads) exited with $code: $(head -c 300 "$name/run$run/stderr.txt")"
      return
    fi
  done
  for out in "${outputs[@]}"; do
    if [[ ! -s "$name/run1/$out" ]]; then fail "$name" "$out not written"; continue; fi
    for run in 1 2 3 4; do
      canonical "$name/run$run/$out" >"$name/run$run/$out.canonical" 2>/dev/null
    done
    for run in 2 3 4; do
      if cmp -s "$name/run1/$out.canonical" "$name/run$run/$out.canonical"; then ok; else
        fail "$name" "$out of run $run ($(((run + 1) / 2)) BLAS threads) differs from run 1 (1 thread)"
      fi
    done
  done
}

mkdir -p meshes
# 10368 vertices: from 10k rows on SparseCholesky factorises with CHOLMOD (and its BLAS), below
# with Eigen's solver, which needs no pinning.
"$RICCI" generate torus --resolution 72 -o meshes/torus.obj >/dev/null || exit 2
"$RICCI" generate surface --genus 2 -o meshes/genus2.obj >/dev/null || exit 2
"$RICCI" generate icosphere -o meshes/sphere.obj >/dev/null || exit 2
M="$WORK/meshes"

check_case flow_torus result.json -- flow "$M/torus.obj" -o result.json
check_case flow_genus2 result.json -- flow "$M/genus2.obj" --target uniform -o result.json
check_case param_sphere uv.obj report.json -- \
  param "$M/sphere.obj" --cones 8 --quantize -o uv.obj --report report.json
check_case param_torus uv.obj report.json -- param "$M/torus.obj" -o uv.obj --report report.json

finish
