#!/usr/bin/env bash
# The Python package the usual way, offline (setup.py): `pip install ./` of the checkout into a
# fresh virtual environment (--system-site-packages: Debian's numpy), then, from outside the source
# tree, ricci.__version__ against CMakeLists.txt, a generated mesh parameterized, a one-mesh
# ricci.batch (which must run the program bundled in the package), no RUNPATH into the build or
# source tree and no unresolved library; then `pip wheel` of the checkout, that wheel installed
# into a second fresh venv and checked the same way; then `pip uninstall -y ricci` from both, after
# which `import ricci` must fail.
#
# Usage: [PYTHON=/usr/bin/python3] [RICCI_CMAKE_BUILD_DIR=DIR] bash tests/python/pip_install_test.sh
#        SOURCE_DIR SCRATCH_DIR
# RICCI_CMAKE_BUILD_DIR: a CMake build folder that setup.py reuses for both pip builds (CTest
# passes its own build tree, so that pip compiles nothing there). Without it the two builds share
# SCRATCH_DIR/cmake-build: one full Release build of the library, the program and the module.
set -euo pipefail

source_dir=$(cd "$1" && pwd)
work=$2
python=${PYTHON:-/usr/bin/python3}
rm -rf "$work"
mkdir -p "$work"
work=$(cd "$work" && pwd)

# Nothing from the caller's environment may find a ricci other than the installed one, and no
# step may need the network (pip fails at once instead of retrying an index).
unset PYTHONPATH PYTHONHOME RICCI_EXECUTABLE VIRTUAL_ENV
export PIP_NO_INDEX=1 PIP_NO_INPUT=1 PIP_DISABLE_PIP_VERSION_CHECK=1 PYTHONDONTWRITEBYTECODE=1
own_build=0
if [[ -z "${RICCI_CMAKE_BUILD_DIR:-}" ]]; then
  export RICCI_CMAKE_BUILD_DIR="$work/cmake-build"
  own_build=1
fi
expected=$(sed -n 's/^project(ricci VERSION \([0-9.]*\).*/\1/p' "$source_dir/CMakeLists.txt")
[[ -n "$expected" ]] || { echo "pip_install_test: no project version in CMakeLists.txt" >&2; exit 1; }

step() { echo "pip_install_test: [$SECONDS s] $*"; }
fail() { echo "pip_install_test: FAILED: $*" >&2; exit 1; }

# check VENV: the installed package, run from $work (not the source tree).
check() {
  local venv=$1
  (cd "$work" && "$venv/bin/python" - "$venv" "$expected" "$work" <<'EOF'
import os, subprocess, sys
venv, expected, work = sys.argv[1], sys.argv[2], sys.argv[3]
import numpy as np
import ricci
from ricci import _batch

package = os.path.dirname(os.path.abspath(ricci.__file__))
assert package.startswith(os.path.realpath(venv) + os.sep) or package.startswith(venv + os.sep), \
    f"ricci imported from {package}, not from {venv}"
assert ricci.__version__ == expected, f"ricci.__version__ {ricci.__version__!r} != {expected!r}"

V, F = ricci.generate.torus(24, 12)
param = ricci.parameterize(V, F)
assert param.converged, param.message
assert np.isfinite(param.uv).all() and param.uv.shape[1] == 2
assert param.distortion.flipped_faces == 0

program = _batch.find_program()
bundled = os.path.join(package, "bin", "ricci")
assert program == bundled, f"ricci.batch runs {program}, not the bundled {bundled}"
mesh = os.path.join(work, os.path.basename(venv) + "-disk.obj")
ricci.write_obj(mesh, *ricci.generate.disk(6))
table = ricci.batch([mesh], os.path.join(work, os.path.basename(venv) + "-batch"), jobs=1)
assert len(table) == 1 and table[0]["outcome"] == "ok", table
assert table[0]["version"] == expected, table[0]["version"]

# The binaries: every library resolved, no RUNPATH into the build or source tree.
build = os.path.realpath(os.environ["RICCI_CMAKE_BUILD_DIR"])
source = os.path.realpath(os.environ["RICCI_SOURCE_DIR"])
for binary in [ricci._ricci.__file__, bundled]:
    ldd = subprocess.run(["ldd", binary], capture_output=True, text=True, check=True).stdout
    assert "not found" not in ldd, f"{binary}:\n{ldd}"
    dynamic = subprocess.run(["readelf", "-d", binary], capture_output=True, text=True,
                             check=True).stdout
    for line in dynamic.splitlines():
        if "RPATH" in line or "RUNPATH" in line:
            for entry in line.split("[", 1)[1].rstrip("]").split(":"):
                real = os.path.realpath(entry) if entry else ""
                assert not (real and (real.startswith(build) or real.startswith(source))), \
                    f"{binary}: {line.strip()}"
print(f"pip_install_test: {venv}: ricci {ricci.__version__} from {package}, "
      f"parameterize and batch ok")
EOF
  )
}

# check_gone VENV: after `pip uninstall -y ricci`, the venv has no ricci.
check_gone() {
  local venv=$1
  if (cd "$work" && "$venv/bin/python" -c "import ricci" 2>/dev/null); then
    fail "import ricci still works in $venv after pip uninstall"
  fi
  if compgen -G "$venv/lib/python3*/site-packages/ricci*" >/dev/null; then
    fail "pip uninstall left $(echo "$venv"/lib/python3*/site-packages/ricci*)"
  fi
}

export RICCI_SOURCE_DIR="$source_dir"
step "venv (--system-site-packages) for $python"
"$python" -m venv --system-site-packages "$work/venv"
step "pip install ./ in $source_dir (CMake build folder $RICCI_CMAKE_BUILD_DIR)"
(cd "$source_dir" && "$work/venv/bin/python" -m pip install ./)
check "$work/venv"

step "pip wheel --no-deps ./ -w $work/dist"
(cd "$source_dir" && "$work/venv/bin/python" -m pip wheel --no-deps ./ -w "$work/dist")
wheels=("$work"/dist/ricci-"$expected"-*.whl)
[[ ${#wheels[@]} == 1 && -f "${wheels[0]}" ]] || fail "no single wheel in $work/dist: $(ls "$work/dist")"
step "wheel ${wheels[0]##*/}"
# Elsewhere: a second venv, with the CMake build folder gone when it was this test's own.
if [[ $own_build == 1 ]]; then rm -rf "$RICCI_CMAKE_BUILD_DIR"; fi
"$python" -m venv --system-site-packages "$work/venv2"
(cd "$work" && "$work/venv2/bin/python" -m pip install "${wheels[0]}")
check "$work/venv2"

step "pip uninstall -y ricci"
"$work/venv/bin/python" -m pip uninstall -y ricci
check_gone "$work/venv"
"$work/venv2/bin/python" -m pip uninstall -y ricci
check_gone "$work/venv2"
# The checkout is as it was: no setuptools scratch (build/lib*, *.egg-info) left in it.
if compgen -G "$source_dir/python/*.egg-info" >/dev/null || compgen -G "$source_dir/*.egg-info" >/dev/null; then
  fail "pip left an egg-info in the checkout"
fi
step "done"
