#pragma once
/// \file
/// Internal: flow_mesh for a caller that holds the input's connectivity itself and gives it to
/// the result afterwards (parameterize), sparing a copy of the whole topology.

#include "ricci/flow/mesh_flow.hpp"

namespace ricci::mesh_flow_internal {

/// flow_mesh(mesh, topology, options), except that MeshFlowResult::topology is left empty when
/// the flow kept the input's triangulation (no flips, or only doubled components): the caller
/// then sets it to `topology` itself. \return with `kept_input_topology` saying which
MeshFlowResult flow_mesh_keeping_topology(const Mesh& mesh, const Topology& topology,
                                          const MeshFlowOptions& options,
                                          bool& kept_input_topology);

}  // namespace ricci::mesh_flow_internal
