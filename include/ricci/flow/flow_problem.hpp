#pragma once
/// \file
/// What every stage of a flow or a parameterization reads about its mesh, built once per run:
/// the connectivity, the input's edge lengths and the conformal structure (for the Thurston
/// scheme, the radius fit). The stages (cone selection, the flow and its fallbacks, the cut and
/// the layout) take this object instead of the mesh, so none of them builds these again; a test
/// counts the builds (ricci/mesh/build_counts.hpp).

#include <Eigen/Core>

#include "ricci/mesh/mesh.hpp"
#include "ricci/mesh/topology.hpp"
#include "ricci/metric/scheme.hpp"

namespace ricci {

/// A mesh with its connectivity, 3D edge lengths and conformal structure.
struct FlowProblem {
  /// The mesh (not owned: it must outlive the problem and stay unchanged; a stage that changes
  /// the mesh, such as raising a cone's valence, makes a new problem for the new mesh).
  const Mesh* mesh = nullptr;
  Topology topology;              ///< build_topology(mesh)
  Eigen::VectorXd input_lengths;  ///< #E 3D lengths (input_edge_lengths)
  StructureOptions structure_options;
  StructureResult structure;  ///< make_conformal_structure(topology, input_lengths, options)
};

/// Builds the problem of a mesh.
/// \pre the mesh passed validate_mesh
/// \throw TopologyError, InvalidInput as build_topology and make_conformal_structure
FlowProblem make_flow_problem(const Mesh& mesh, const StructureOptions& options = {});
/// The same with the mesh's connectivity at hand (moved in). \pre topology = build_topology(mesh)
FlowProblem make_flow_problem(const Mesh& mesh, Topology topology,
                              const StructureOptions& options = {});

}  // namespace ricci
