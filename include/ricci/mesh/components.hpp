#pragma once
/// \file
/// Splitting a mesh into its connected components so that each can be solved on its own.

#include <vector>

#include "ricci/mesh/mesh.hpp"
#include "ricci/mesh/topology.hpp"

namespace ricci {

/// One connected component as a mesh of its own, with maps back to the whole mesh.
struct Submesh {
  Mesh mesh;
  std::vector<int> vertex_map;  ///< #V of the submesh: vertex index in the whole mesh
  std::vector<int> face_map;    ///< #F of the submesh: face index in the whole mesh
};

/// Splits a mesh into its connected components (in the order of topology.components).
std::vector<Submesh> split_components(const Mesh& mesh, const Topology& topology);

}  // namespace ricci
