#pragma once
/// \file
/// The cut graph (tutorial section 5.4, THEORY.md section 7): a set of edges that, once the mesh
/// is sliced along them, leaves one topological disk, passing through every cone and touching
/// every boundary loop. Built from a homology basis by tree-cotree, joined to cones and boundaries
/// by shortest paths, pruned of branches that end nowhere.
///
/// Boundaries: the trees and paths run on the mesh with every boundary loop contracted to one
/// node (as if the loop were capped by a virtual vertex joined to it by zero-length spokes). That
/// closed surface has the genus of the component, so tree-cotree gives exactly 2 g generators;
/// a path that passes through a loop node continues along the boundary, which is on the disk's
/// boundary anyway, so only real interior edges are ever cut.

#include <vector>

#include <Eigen/Core>

#include "ricci/mesh/topology.hpp"

namespace ricci {

/// Options of cut_graph.
struct CutGraphOptions {
  std::vector<int> cones;  ///< vertices the cut must pass through (cone singularities)
  /// Vertex the primal shortest-path tree grows from, in its own component (other components
  /// pick theirs); -1 picks a central one per component (the vertex farthest, along the given
  /// edge lengths, from the boundary and the cones; the smallest vertex of a closed component
  /// without cones). Genus-0 components grow no tree and ignore it.
  int root_vertex = -1;
  /// #E flags, or empty: edges the cut must never contain, e.g. the diagonals a polygon mesh's
  /// triangulation added (polygon_diagonals of ricci/mesh/polygons.hpp), so that every polygon
  /// stays whole on the sliced mesh. The trees and paths then run on the other edges, the cotree
  /// takes every uncut edge, and a single cut edge between two cones is widened along the rest
  /// of its polygon. The triangles joined across uncut edges must form a tree each (a
  /// triangulated polygon does); flags on boundary edges are ignored.
  std::vector<char> uncut_edges;
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
/// Per component: tree-cotree generators (genus >= 1), then shortest paths join the interior
/// cones and the boundary loops to the cut, nearest first, starting from the generators (genus
/// >= 1), the first boundary loop (genus 0 with boundary) or the smallest cone (closed genus 0);
/// then branches ending at a vertex that is neither a cone nor on a boundary are pruned.
/// Slicing along the result leaves one topological disk per component, except that a closed
/// genus-0 component with fewer than two cones gets an empty cut and stays a sphere (a cone
/// there is a node without edges), and a disk without interior cones gets an empty cut. On a
/// closed genus-0 component whose cut would be a single edge between two adjacent cones, the two
/// other edges of the cheaper of its faces are cut instead (one edge whose two ends keep a single
/// copy each cannot be opened; with uncut edges the rest of its polygon is cut). Cones on a
/// boundary need no path. O(E log E); deterministic.
/// \param lengths #E edge lengths the shortest paths follow (e.g. the input mesh's lengths)
/// \throw InvalidInput when a cone or the root vertex is out of range or belongs to no face, when
///        lengths does not hold #E finite values >= 0, or when uncut_edges is neither empty nor
///        #E flags, or joins triangles in a loop (naming an edge that closes it)
CutGraph cut_graph(const Topology& topology, const Eigen::VectorXd& lengths,
                   const CutGraphOptions& options = {});

/// The mesh sliced open along a cut: every cut vertex is duplicated once per wedge of faces
/// between consecutive cut (or boundary) edges around it.
struct CutMesh {
  Triangles triangles;           ///< #F by 3, same faces and corner order, new vertex indices
  std::vector<int> to_original;  ///< per new vertex: the vertex of the mesh it copies
  Topology topology;             ///< connectivity of the sliced mesh
};

/// Slices a mesh along the cut edges. Vertex v of the mesh keeps index v for its first copy (the
/// wedge holding its smallest corner 3 f + k), so to_original starts with the identity over #V
/// (unreferenced vertices included); further copies are numbered from #V on in the order of
/// their smallest corner.
/// \throw InvalidInput when cut.is_cut_edge does not hold #E flags
CutMesh slice(const Topology& topology, const CutGraph& cut);

/// #V flags: 1 for the vertices of the cut's edges (the seam vertices, whose copies the slicing
/// separates). A cone the cut reaches by no edge (one cone on a sphere) is not among them.
std::vector<char> cut_vertices(const Topology& topology, const CutGraph& cut);

}  // namespace ricci
