#include "ricci/mesh/build_counts.hpp"

#include <atomic>

namespace ricci {
namespace {

std::atomic<long> topologies{0}, input_lengths{0}, structures{0}, cone_models{0}, cut_meshes{0};
std::atomic<long long> nanoseconds{0};
/// Builds in progress on this thread (a cone model builds a structure inside).
thread_local int depth = 0;

}  // namespace

BuildCounts build_counts() {
  constexpr auto relaxed = std::memory_order_relaxed;
  return {topologies.load(relaxed), input_lengths.load(relaxed),
          structures.load(relaxed), cone_models.load(relaxed),
          cut_meshes.load(relaxed), 1e-9 * static_cast<double>(nanoseconds.load(relaxed))};
}

build_counting::Scope::Scope(Kind kind) : outermost_(depth++ == 0) {
  constexpr auto relaxed = std::memory_order_relaxed;
  switch (kind) {
    case Kind::Topology:
      topologies.fetch_add(1, relaxed);
      break;
    case Kind::InputLengths:
      input_lengths.fetch_add(1, relaxed);
      break;
    case Kind::Structure:
      structures.fetch_add(1, relaxed);
      break;
    case Kind::ConeModel:
      cone_models.fetch_add(1, relaxed);
      break;
    case Kind::CutMesh:
      cut_meshes.fetch_add(1, relaxed);
      break;
  }
  if (outermost_) start_ = std::chrono::steady_clock::now();
}

build_counting::Scope::~Scope() {
  --depth;
  if (!outermost_) return;
  const auto elapsed = std::chrono::steady_clock::now() - start_;
  nanoseconds.fetch_add(std::chrono::duration_cast<std::chrono::nanoseconds>(elapsed).count(),
                        std::memory_order_relaxed);
}

}  // namespace ricci
