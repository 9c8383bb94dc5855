#pragma once
// Private to the mesh module: the passes of repair_mesh (repair.cpp), declared here so that each
// is tested on its own (tests/mesh/repair_passes_test.cpp).

#include <array>
#include <utility>
#include <vector>

#include "ricci/mesh/mesh.hpp"
#include "ricci/mesh/repair.hpp"

namespace ricci::mesh_detail {

/// Step (1), welding. representative[v]: the vertex v is welded onto (itself when none), the
/// smallest index of the vertices welded together; only referenced vertices with finite
/// coordinates take part, since NaN compares unequal to everything.
/// \param referenced #V: 1 where some face uses the vertex
/// \param tolerance 0 for equal positions only, else relative to the bounding-box diagonal of
///        the vertices that take part (a chain of close vertices welds into one)
std::vector<int> weld(const Positions& P, const std::vector<char>& referenced, double tolerance);

/// Step (2), duplicate faces: duplicate_of[f] is the earliest included face on the same three
/// vertices as f (in any order), -1 where f is the first (or only) such face or not included.
/// \param included #F: 1 where the face takes part
std::vector<int> find_duplicate_faces(const Triangles& T, const std::vector<char>& included);

/// Step (3) at one non-manifold edge: pairs the faces around edge (a, b) that bound the same
/// wedge of space, as (h, g) with h the halfedge of the face running b -> a just below the face
/// of g (running a -> b) by the angle of their third vertex around the edge. Halfedge
/// h = 3 i + k lies opposite corner k of face kept[i] of T. Faces left without a partner are to
/// be detached at this edge.
/// \param halfedges the halfedges of the kept faces on edge (a, b), ascending
std::vector<std::pair<int, int>> pair_around_edge(const Positions& P, const Triangles& T,
                                                  const std::vector<int>& kept,
                                                  const std::vector<int>& halfedges, int a, int b);

/// Steps (3) and (4) of repair_mesh on the kept faces (kept[i] is the row of T of kept face i,
/// T the welded triangles): which faces stay joined, the vertex copies, the orientation.
struct Split {
  std::vector<int> corner_output;   ///< 3 #kept: output vertex of each corner
  std::vector<int> vertex_map;      ///< output vertex -> (welded) input vertex
  std::vector<signed char> flip;    ///< #kept: 1 where the face must be reversed
  std::vector<int> non_orientable;  ///< a kept face of each non-orientable component
  std::vector<std::array<int, 2>> non_manifold_edges;  ///< edges with more than two faces
};

/// Splits non-manifold edges (with options.split_non_manifold) and gives every vertex one copy
/// per fan of faces (output vertices: the first fan of each input vertex in input order, then
/// the extra copies), then, with options.orient, the flips that orient each orientable
/// component by its majority.
/// \param nv the number of input vertices (T's entries are below it)
Split split_and_orient(const Positions& P, const Triangles& T, const std::vector<int>& kept, int nv,
                       const RepairOptions& options);

}  // namespace ricci::mesh_detail
