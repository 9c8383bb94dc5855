#pragma once
/// \file
/// The cut graph (tutorial section 5.4, THEORY.md section 7): a set of edges that, once the mesh
/// is sliced along them, leaves one topological disk, passing through every cone and touching
/// every boundary loop. Built from a homology basis by tree-cotree, joined to cones and boundaries
/// by shortest paths, pruned of branches that end nowhere.

#include <vector>

#include <Eigen/Core>

#include "ricci/mesh/topology.hpp"

namespace ricci {

/// Options of cut_graph.
struct CutGraphOptions {
  std::vector<int> cones;  ///< vertices the cut must pass through (cone singularities)
  /// Vertex the primal shortest-path tree grows from; -1 picks a central one (the vertex
  /// farthest, along edges, from the boundary and the cones; vertex 0 on a closed mesh without
  /// cones).
  int root_vertex = -1;
};

/// A cut graph on a mesh.
struct CutGraph {
  std::vector<char> is_cut_edge;  ///< #E: 1 for edges of the cut (boundary edges are never cut
                                  ///< edges: the boundary is part of the disk's boundary anyway)
  int num_generators = 0;         ///< homology generators found (2 g per component)
  /// Nodes: cut vertices whose number of cut edges plus boundary edges is not 2, and the cones.
  std::vector<int> nodes;
  /// Segments: the cut split at nodes; each a path of vertices from a node to a node (a closed
  /// loop with no node starts and ends at the same vertex).
  std::vector<std::vector<int>> segments;
  double length = 0;  ///< total length of the cut edges in the given lengths
};

/// Computes a cut graph of a manifold mesh (any number of components, genus and boundaries).
/// \param lengths #E edge lengths the shortest paths follow (e.g. the input mesh's lengths)
/// \throw InvalidInput when a cone is out of range
CutGraph cut_graph(const Topology& topology, const Eigen::VectorXd& lengths,
                   const CutGraphOptions& options = {});

/// The mesh sliced open along a cut: every cut vertex is duplicated once per wedge of faces
/// between consecutive cut (or boundary) edges around it.
struct CutMesh {
  Triangles triangles;            ///< #F by 3, same faces and corner order, new vertex indices
  std::vector<int> to_original;   ///< per new vertex: the vertex of the mesh it copies
  Topology topology;              ///< connectivity of the sliced mesh
};

/// Slices a mesh along the cut edges.
CutMesh slice(const Topology& topology, const CutGraph& cut);

}  // namespace ricci
