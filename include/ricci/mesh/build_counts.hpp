#pragma once
/// \file
/// How many times the expensive per-mesh structures have been built, and the wall time spent
/// building them, since the program started, over all threads: what a test reads to pin down
/// that a pipeline builds each of them once (ricci/flow/flow_problem.hpp), and what a benchmark
/// reads as the set-up time. One relaxed atomic increment and two clock reads per build, so
/// always on.

#include <chrono>

namespace ricci {

/// Builds counted since the program started.
struct BuildCounts {
  long topologies = 0;     ///< build_topology calls (any mesh: the input, a cut mesh, ...)
  long input_lengths = 0;  ///< input_edge_lengths calls (3D edge lengths of a mesh)
  long structures = 0;     ///< make_conformal_structure calls (the Thurston fit and its kin)
  long cone_models = 0;    ///< build_cone_model calls (the linearised flow, factorised)
  long cut_meshes = 0;     ///< topologies of cut meshes (slice), counted in `topologies` too
  /// Wall time inside the outermost of these builds (a build inside another counts once),
  /// summed over threads.
  double seconds = 0;

  /// The builds made between `earlier` and this reading.
  BuildCounts operator-(const BuildCounts& earlier) const {
    return {topologies - earlier.topologies, input_lengths - earlier.input_lengths,
            structures - earlier.structures, cone_models - earlier.cone_models,
            cut_meshes - earlier.cut_meshes, seconds - earlier.seconds};
  }
};

/// The counts so far.
BuildCounts build_counts();

/// What the builders use (not for users): one Scope for the duration of each build.
namespace build_counting {
enum class Kind { Topology, InputLengths, Structure, ConeModel, CutMesh };
class Scope {
 public:
  explicit Scope(Kind kind);
  ~Scope();
  Scope(const Scope&) = delete;
  Scope& operator=(const Scope&) = delete;

 private:
  bool outermost_;
  std::chrono::steady_clock::time_point start_;
};
}  // namespace build_counting

}  // namespace ricci
