#pragma once
/// \file
/// Internal: flow_mesh for a caller that holds the input's connectivity itself and gives it to
/// the result afterwards (parameterize), sparing a copy of the whole topology.

#include <chrono>

#include "ricci/flow/mesh_flow.hpp"

namespace ricci::mesh_flow_internal {

/// flow_mesh on a problem, except that MeshFlowResult::topology is left empty when the flow kept
/// the input's triangulation (no flips, or only doubled components): the caller then sets it to
/// the problem's topology itself (moved, when the problem is done). \return with
/// `kept_input_topology` saying which
MeshFlowResult flow_mesh_keeping_topology(const FlowProblem& problem,
                                          const MeshFlowOptions& options,
                                          bool& kept_input_topology);

/// The same from the problem's parts; `start` begins the result's setup and total times.
MeshFlowResult flow_mesh_keeping_topology(const Topology& topology,
                                          const Eigen::VectorXd& input_lengths,
                                          StructureResult structure, const MeshFlowOptions& options,
                                          bool& kept_input_topology,
                                          std::chrono::steady_clock::time_point start);

}  // namespace ricci::mesh_flow_internal
