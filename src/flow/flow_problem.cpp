#include "ricci/flow/flow_problem.hpp"

#include <utility>

namespace ricci {

FlowProblem make_flow_problem(const Mesh& mesh, const StructureOptions& options) {
  return make_flow_problem(mesh, build_topology(mesh.triangles, mesh.num_vertices()), options);
}

FlowProblem make_flow_problem(const Mesh& mesh, Topology topology,
                              const StructureOptions& options) {
  FlowProblem problem;
  problem.mesh = &mesh;
  problem.topology = std::move(topology);
  problem.input_lengths = input_edge_lengths(mesh, problem.topology);
  problem.structure_options = options;
  problem.structure = make_conformal_structure(problem.topology, problem.input_lengths, options);
  return problem;
}

}  // namespace ricci
