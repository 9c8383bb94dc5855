#!/usr/bin/env bash
# Installs the Debian packages ricci builds and tests with; installs nothing that is already there.
set -euo pipefail
packages=(
  cmake g++ make clang-format
  # .ci/run's static analysis (.clang-tidy; run-clang-tidy comes with it).
  clang-tidy
  libeigen3-dev libsuitesparse-dev
  # CHOLMOD's supernodal factorisation runs its dense kernels through BLAS: OpenBLAS makes it
  # about twice as fast as the reference BLAS on a 500k-vertex Hessian.
  libopenblas0-pthread
  libcli11-dev nlohmann-json3-dev
  libgtest-dev libbenchmark-dev
  # Python module (built against Debian's own /usr/bin/python3) and its tests; pictures.
  pybind11-dev python3-dev python3-numpy python3-pytest
  # `pip install ./` offline (setup.py, tests/python/pip_install_test.sh): Debian's pip,
  # setuptools and wheel, and venv.
  python3-pip python3-setuptools python3-wheel python3-venv
  libcairo2-dev
  libpng-dev
  # The web viewer inlines Debian's three.js; its test opens the pages in headless Chromium.
  libjs-three chromium
  # glTF binary output (--format glb) and its read-back test.
  libtinygltf-dev
  # `ricci batch` on MPI ranks (optional at build time; its test runs mpirun).
  openmpi-bin libopenmpi-dev
  # `ricci blender-addon` writes the add-on's zip (libzip); its test runs Debian's Blender
  # headless (Blender 3.4 runs on the same Python 3.11 as the module), and with a window under a
  # virtual X server for the modal run and undo.
  libzip-dev blender xvfb xauth
  # Fuzzing (fuzz/run.sh): clang++ with libFuzzer and the sanitizer runtimes.
  clang libclang-rt-14-dev
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "install-deps: installing ${missing[*]}"
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}" >/dev/null
fi
