#pragma once
/// \file
/// Internal: flow_mesh for a caller that holds the input's connectivity itself and gives it to
/// the result afterwards (parameterize), sparing a copy of the whole topology.

#include <memory>

#include "ricci/flow/mesh_flow.hpp"

namespace ricci::mesh_flow_internal {

/// flow_mesh(mesh, topology, options), except that the result's intrinsic triangulation (and the
/// flow of a single component) only refers to `topology` as its input, without a copy: the
/// caller hands it over with adopt_input_topology before `topology` goes.
/// \return with `kept_input_topology` true (the result refers to `topology`)
MeshFlowResult flow_mesh_keeping_topology(const Mesh& mesh, const Topology& topology,
                                          const MeshFlowOptions& options,
                                          bool& kept_input_topology);

/// Makes `topology` (the connectivity flow_mesh_keeping_topology was given, or the same one
/// moved elsewhere) the input of the result's intrinsic triangulations that referred to it.
void adopt_input_topology(MeshFlowResult& result, std::shared_ptr<const Topology> topology);

}  // namespace ricci::mesh_flow_internal
