#pragma once
/// \file
/// The summary `ricci info` prints: counts, topology, smallest angle and every defect.

#include <vector>

#include "ricci/mesh/mesh.hpp"
#include "ricci/mesh/validate.hpp"

namespace ricci {

/// Per-component topology.
struct ComponentInfo {
  int vertices = 0, edges = 0, faces = 0, boundary_loops = 0, euler_characteristic = 0, genus = 0;
};

/// Summary of a mesh. Topological fields are -1 when defects keep them from being defined
/// (non-manifold or inconsistently oriented meshes).
struct MeshInfo {
  int vertices = 0;               ///< referenced vertices
  int unreferenced_vertices = 0;  ///< vertices no face uses
  int edges = -1;
  int faces = 0;
  int components = -1;
  int boundary_loops = -1;
  int euler_characteristic = -1;  ///< V - E + F over referenced vertices, when manifold
  int genus = -1;                 ///< total over components, when manifold
  std::vector<ComponentInfo> component_info;
  double min_angle_degrees = 0;  ///< smallest corner angle over all faces
  double max_angle_degrees = 0;  ///< largest corner angle over all faces
  double bounding_box_diagonal = 0;
  ValidationReport validation;  ///< every defect found
};

/// Computes the summary; never throws on defective meshes (that is its purpose).
MeshInfo mesh_info(const Mesh& mesh);

}  // namespace ricci
