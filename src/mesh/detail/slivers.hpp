#pragma once
// Private to the mesh module: the exact removal of zero-area faces whose three vertices are
// distinct (slivers: one vertex on the segment of the other two), step (2b) of repair_mesh.

#include <string>
#include <vector>

#include "ricci/mesh/mesh.hpp"

namespace ricci::mesh_detail {

/// Why a zero-area face is left as it is.
enum class SliverLeft {
  Needle,        ///< its middle vertex nearly coincides with an end of its longest edge
  CrowdedEdge,   ///< its longest edge has more than two faces
  ExistingEdge,  ///< the split would give an edge that the mesh already has
  Unresolved,    ///< a chain of zero-area faces that the splits did not resolve
};

/// What remove_slivers did. Rows are those of its input triangles.
struct SliverRemoval {
  /// A face was removed or split; when not, the faces are T as they are, and only `left` and
  /// `left_why` are filled.
  bool changed = false;
  Triangles triangles;      ///< the faces afterwards, the pieces of a row in its place
  std::vector<int> origin;  ///< per output face: the input row it is (or is a piece of)
  std::vector<char> piece;  ///< per output face: 1 where it is a piece of its input row
  /// Input rows of zero area of which no face is left, ascending: slivers absorbed into the
  /// face across their longest edge, or removed from the boundary (they cover nothing).
  std::vector<int> removed;
  std::vector<char> on_boundary;     ///< per entry of removed: 1 where the boundary took it
  std::vector<int> split;            ///< input rows of positive area split into pieces, ascending
  std::vector<int> left;             ///< input rows of the zero-area faces left, ascending
  std::vector<SliverLeft> left_why;  ///< per entry of left
};

/// Removes the zero-area faces of T (is_zero_area with `tolerance`) whose middle vertex w lies on
/// their longest edge uv, without changing the surface: where uv is a boundary edge the sliver
/// covers nothing and is removed; otherwise the face across uv, (u, v, x) in its own order, is
/// split into (u, w, x) and (w, v, x), whose union is that face and the sliver together, and the
/// sliver is removed. A piece that has zero area again (a chain of slivers along one line) is
/// treated in turn; splits across a neighbour that is itself a sliver are made only when no
/// other sliver can be removed, and only where uv is that neighbour's longest edge too; a bound
/// on the number of splits ends every case. What cannot be removed exactly is left and listed.
/// Faces are taken as they come: orientation and manifoldness are checked afterwards.
/// \pre T's faces use three distinct vertices, and no two faces the same vertex set
SliverRemoval remove_slivers(const Positions& P, const Triangles& T, double tolerance);

/// "its middle vertex nearly coincides with an end of its longest edge (a needle, not a
/// sliver)" and the like, for the repair report.
std::string sliver_left_reason(SliverLeft why);

}  // namespace ricci::mesh_detail
