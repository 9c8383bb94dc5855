#pragma once
/// \file
/// Repair of the defects that keep a triangle soup from being an oriented manifold surface but
/// that have one obvious fix: duplicate vertices, duplicate and collapsed faces, zero-area faces
/// with a vertex on their longest edge (slivers, removed without changing the surface),
/// non-manifold edges and vertices, inconsistent orientation and unreferenced vertices. What no
/// single fix answers is left alone and reported by validation afterwards: zero-area faces that
/// cannot be removed exactly, non-finite coordinates and non-orientable components.

#include <array>
#include <string>
#include <vector>

#include "ricci/mesh/mesh.hpp"
#include "ricci/mesh/validate.hpp"

namespace ricci {

/// Options of repair_mesh.
struct RepairOptions {
  /// Weld vertices at the same position into one (the one with the smallest index).
  bool weld_vertices = true;
  /// Weld vertices closer than this times the bounding-box diagonal of the finite referenced
  /// vertices (a chain of close vertices welds into one); 0 welds only exactly equal positions.
  double weld_tolerance = 0;
  /// Remove zero-area faces whose three vertices are distinct, one on the segment of the other
  /// two (slivers): on the boundary outright, elsewhere by splitting the face across their
  /// longest edge at that vertex (the surface stays the same; see repair_mesh).
  bool remove_slivers = true;
  /// Zero area as validation sees it (ValidationOptions::zero_area_tolerance): twice the area at
  /// most this times the longest edge squared.
  double zero_area_tolerance = ValidationOptions{}.zero_area_tolerance;
  /// Split edges with more than two faces and vertices whose faces form several fans.
  bool split_non_manifold = true;
  /// Reverse faces so that every orientable component is consistently oriented (the side with
  /// more faces keeps its orientation).
  bool orient = true;
  /// Keep only the connected component with the most faces (the first on ties), for algorithms
  /// that take one surface (parameterize); the others are removed and reported.
  bool largest_component_only = false;
  /// Examples kept per kind of change.
  int max_examples = 5;
};

/// How many elements one kind of change touched, with the first few as examples. Indices are
/// those of the input mesh.
struct RepairCount {
  int count = 0;
  std::vector<int> examples;  ///< at most RepairOptions::max_examples element indices
};

/// What repair_mesh changed, and what it could not repair. Indices are the input's.
struct RepairReport {
  int input_vertices = 0, input_faces = 0;
  int output_vertices = 0, output_faces = 0;
  /// Vertices merged into an earlier vertex at the same position; examples: the merged ones.
  RepairCount welded_vertices;
  /// Faces removed because they use a vertex twice (from the start or after welding).
  RepairCount repeated_vertex_faces_removed;
  /// Faces removed because an earlier face has the same three vertices (in any order).
  RepairCount duplicate_faces_removed;
  /// Zero-area faces with a vertex on their longest edge (slivers) removed: absorbed by
  /// splitting the face across that edge, or, on the boundary, removed outright (they cover
  /// nothing). Examples: input faces (a piece of an input face counts as that face).
  RepairCount slivers_removed;
  int boundary_slivers_removed = 0;  ///< of slivers_removed, those on the boundary
  /// Faces split in two at a sliver's middle vertex; examples: input faces.
  RepairCount faces_split;
  /// Edges (after welding) with more than two faces whose faces were regrouped into pairs.
  int non_manifold_edges_split = 0;
  std::vector<std::array<int, 2>> non_manifold_edge_examples;  ///< (smaller, larger) vertex
  /// Vertices given one copy per fan of faces (non-manifold vertices, and the ends of split
  /// edges); examples: input vertices.
  RepairCount non_manifold_vertices_split;
  int vertex_copies_added = 0;  ///< output vertices beyond one per input vertex
  /// Faces reversed to orient their component consistently.
  RepairCount faces_flipped;
  /// Vertices no face uses (from the start, or after faces were removed), dropped.
  RepairCount unreferenced_vertices_dropped;
  /// With largest_component_only: the components removed (examples: one input face of each)
  /// and their faces.
  RepairCount smaller_components_removed;
  int smaller_component_faces_removed = 0;
  /// Not repaired: components that admit no consistent orientation; examples: one input face of
  /// each (left as they were).
  RepairCount non_orientable_components;
  /// Not repaired: zero-area faces that no exact removal answers (a vertex nearly on another, a
  /// longest edge with more than two faces, ...); examples: input faces (left as they were).
  RepairCount zero_area_faces_left;
  /// One line per kind of change, e.g. "welded 403 vertices onto earlier vertices at the same
  /// position (e.g. vertex 17 onto vertex 3)", then one per defect left unrepaired.
  std::vector<std::string> messages;

  /// True when the mesh was changed at all.
  bool changed() const;
};

/// The repaired mesh, how it relates to the input, and the report.
struct RepairResult {
  Mesh mesh;  ///< the repaired mesh
  /// #V: input vertex each output vertex copies (several outputs for a split vertex).
  std::vector<int> vertex_map;
  /// #F: input face each output face comes from; its corners are the input's in the same order,
  /// or with corners 1 and 2 exchanged where face_flipped is set (except where face_split is).
  std::vector<int> face_map;
  /// #F: 1 where the face was reversed (for a piece: it faces the other way than its input face)
  std::vector<char> face_flipped;
  /// #F: 1 where the face is a piece of input face face_map[f], which was split at a sliver's
  /// vertex (RepairReport::faces_split): the pieces of a face cover it exactly, and a piece's
  /// corners are corners of the input face or that vertex.
  std::vector<char> face_split;
  /// #V of the input: the vertex each input vertex was welded onto (itself when it was not);
  /// an input vertex v appears in the output as the copies of weld_map[v].
  std::vector<int> weld_map;
  RepairReport report;
};

/// Repairs a triangle soup, in this order: (1) welds vertices at equal (or, with a tolerance,
/// close) positions; (2) removes faces that use a vertex twice and faces with the same vertex
/// set as an earlier face, then zero-area faces (u, w, v) whose vertex w lies on their longest
/// edge uv (slivers): where uv is a boundary edge the sliver covers nothing and goes; otherwise
/// the face across uv, (u, v, x) in its own order, becomes (u, w, x) and (w, v, x), the same
/// surface without the sliver (a piece of zero area is treated in turn, so chains of slivers
/// along a line resolve; a bound on the number of splits ends every case); (3) splits non-manifold
/// edges, keeping together the pairs of faces that bound the same wedge of space around the edge
/// (its faces sorted by angle; pairs that would make an orientable surface non-orientable are
/// detached), and gives every vertex one copy per fan of faces; (4) reverses faces so that each
/// orientable component is consistently oriented, then splits again on the oriented faces while
/// that saves vertex copies; (5) drops vertices no face uses (and, when asked, every component but
/// the largest). A mesh without such defects comes back unchanged (identity maps). Zero-area faces
/// that cannot be removed exactly, non-finite coordinates and non-orientable components are left as
/// they are: validate the result (report.messages names what is left, and why). \param mesh #V by 3
/// positions and #F by 3 triangles \throw InvalidInput naming the face when a vertex index is out
/// of range, or when an option
///        is out of range (weld_tolerance negative, not finite, or below 1e-15 but not 0)
RepairResult repair_mesh(const Mesh& mesh, const RepairOptions& options = {});

}  // namespace ricci
