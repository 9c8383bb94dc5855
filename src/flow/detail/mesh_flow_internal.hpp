#pragma once
/// \file
/// Internal: flow_mesh for a caller that holds the input's connectivity itself and gives it to
/// the result afterwards (parameterize), sparing a copy of the whole topology.

#include <chrono>
#include <memory>

#include "ricci/flow/mesh_flow.hpp"

namespace ricci::mesh_flow_internal {

/// flow_mesh on a problem, except that the result's intrinsic triangulation (and the flow of a
/// single component) only refers to the problem's topology as its input, without a copy: the
/// caller hands it over with adopt_input_topology (moved, when the problem is done).
/// \return with `kept_input_topology` true (the result refers to the problem's topology)
MeshFlowResult flow_mesh_keeping_topology(const FlowProblem& problem,
                                          const MeshFlowOptions& options,
                                          bool& kept_input_topology);

/// The same from the problem's parts; `start` begins the result's setup and total times.
MeshFlowResult flow_mesh_keeping_topology(const Topology& topology,
                                          const Eigen::VectorXd& input_lengths,
                                          StructureResult structure, const MeshFlowOptions& options,
                                          bool& kept_input_topology,
                                          std::chrono::steady_clock::time_point start);

/// Makes `topology` (the connectivity flow_mesh_keeping_topology was given, or the same one
/// moved elsewhere) the input of the result's intrinsic triangulations that referred to it.
void adopt_input_topology(MeshFlowResult& result, std::shared_ptr<const Topology> topology);

}  // namespace ricci::mesh_flow_internal
