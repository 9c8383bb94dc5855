// libFuzzer target: the Ricci flow with random targets on small generated meshes. The input bytes
// choose a mesh, a scheme, an initial packing, a solver and a target (flat with a few cones,
// optionally balanced to satisfy Gauss-Bonnet, or uniform). An inadmissible target may be refused
// with InvalidInput; otherwise 30 iterations of the flow must end without a crash, with finite
// results, and either converged or with a status and a message.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <numbers>
#include <vector>

#include "ricci/errors.hpp"
#include "ricci/flow/ricci_flow.hpp"
#include "ricci/flow/target.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/topology.hpp"
#include "ricci/metric/scheme.hpp"

namespace {

// Reads the fuzz input a byte at a time; zeros once it runs out.
class Bytes {
 public:
  Bytes(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::uint8_t next() { return pos_ < size_ ? data_[pos_++] : 0; }
  int below(int n) { return static_cast<int>(next() % n); }
  // A curvature in (-2 pi, 2 pi), a multiple of pi / 32, or (rarely) an extreme value.
  double curvature() {
    const auto raw = static_cast<std::int8_t>(next());
    if (raw == -128) return -1e3;
    return raw * std::numbers::pi / 64.0;
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

ricci::Mesh make_mesh(int choice) {
  switch (choice) {
    case 0:
      return ricci::make_tetrahedron();
    case 1:
      return ricci::make_icosphere(1);
    case 2:
      return ricci::make_disk(3);
    case 3:
      return ricci::make_torus(8, 4);
    default:
      return ricci::make_closed_surface(2, 4);
  }
}

[[noreturn]] void finding(const char* what) {
  std::fprintf(stderr, "fuzz: %s\n", what);
  std::abort();
}

bool finite(const Eigen::VectorXd& v) {
  return v.allFinite();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ricci;
  Bytes in(data, size);
  const Mesh mesh = make_mesh(in.below(5));
  StructureOptions structure_options;
  structure_options.scheme = kSchemeTraits[in.below(static_cast<int>(kSchemeTraits.size()))].scheme;
  structure_options.packing_init = in.below(2) == 0 ? PackingInit::Fit : PackingInit::UnitRadii;
  FlowOptions flow_options;
  flow_options.solver = in.below(4) == 0 ? FlowSolver::Gradient : FlowSolver::Newton;
  flow_options.max_iterations = 30;
  flow_options.reuse_factorization_cg_iterations = in.below(2) == 0 ? 0 : 25;
  constexpr BoundaryMode kModes[] = {BoundaryMode::Free, BoundaryMode::DiskUniform,
                                     BoundaryMode::DiskLength};
  const BoundaryMode boundary = kModes[in.below(3)];
  const int target_kind = in.below(4);  // 0: uniform, 1: flat as given, 2-3: flat, balanced
  const int num_cones = in.below(5);

  const Topology topology = build_topology(mesh.triangles, mesh.num_vertices());
  const Eigen::VectorXd lengths = input_edge_lengths(mesh, topology);
  const StructureResult structure = make_conformal_structure(topology, lengths, structure_options);

  std::vector<Cone> cones;
  for (int i = 0; i < num_cones; ++i) {
    Cone cone;
    cone.vertex = in.below(topology.num_vertices);
    cone.curvature = in.curvature();
    cones.push_back(cone);
  }
  const bool closed = topology.num_boundary_loops() == 0;
  if (target_kind >= 2 && closed && !cones.empty()) {
    // Gauss-Bonnet: put whatever the other cones leave of 2 pi chi on the last one.
    double rest = 2 * std::numbers::pi * topology.euler_characteristic();
    for (std::size_t i = 0; i + 1 < cones.size(); ++i) rest -= cones[i].curvature;
    cones.back().curvature = rest;
  }

  try {
    const Target target = target_kind == 0 ? uniform_target(topology)
                                           : flat_target(topology, cones, boundary, lengths);
    check_admissible(topology, structure.structure, target);
    const FlowResult r = ricci_flow(topology, structure.structure, target, flow_options);
    if (!finite(r.u) || !finite(r.curvature) || !finite(r.target_curvature) || !finite(r.lengths) ||
        !std::isfinite(r.max_error))
      finding("flow result has a non-finite field");
    if (r.u.size() != topology.num_vertices || r.lengths.size() != topology.num_edges)
      finding("flow result has the wrong size");
    if (r.converged != (r.status == FlowStatus::Converged))
      finding("converged flag disagrees with the status");
    if (!r.converged && r.message.empty()) finding("flow stopped without a message");
    if (r.converged && !(r.max_error <= flow_options.tolerance))
      finding("flow converged with max error above the tolerance");
    if (r.iterations > flow_options.max_iterations) finding("flow ran past max_iterations");
  } catch (const InvalidInput&) {
    // An inadmissible target or initial metric: the documented refusal.
  } catch (const SolverError&) {
    // Documented: the linear algebra broke down (reported, not a crash).
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz: flow threw an unexpected exception: %s\n", e.what());
    std::abort();
  }
  return 0;
}
