# Sourced by the bench scripts that take [BUILD_DIR] [OUT_DIR] and run from the repository root.

# bench_paths NAME [BUILD_DIR] [OUT_DIR]: sets build (default build), out (default
# $build/NAME), ricci (the CLI in that build), shared (RICCI_SHARED_MESHES or ../shared/meshes)
# and checkuv (../shared/tools/checkuv.py), the paths every such script starts from.
bench_paths() {
  local name=$1
  shift
  build=${1:-build}
  out=${2:-$build/$name}
  ricci="$PWD/$build/ricci"
  shared=${RICCI_SHARED_MESHES:-$PWD/../shared/meshes}
  checkuv=$PWD/../shared/tools/checkuv.py
}
