#pragma once
/// \file
/// Defect detection for triangle meshes: everything that keeps a mesh from being an oriented,
/// manifold surface with non-degenerate faces. find_defects lists them all (for `ricci info`);
/// validate_mesh throws on the first one.

#include <array>
#include <string>
#include <vector>

#include "ricci/enum_names.hpp"
#include "ricci/mesh/mesh.hpp"

namespace ricci {

/// The kinds of defect, each with its own error.
enum class DefectKind {
  NonFiniteCoordinate,      ///< element: vertex
  IndexOutOfRange,          ///< element: face
  RepeatedVertex,           ///< a face uses one vertex twice; element: face
  ZeroAreaFace,             ///< element: face
  DuplicateFace,            ///< same three vertices as an earlier face; element: face
  NonManifoldEdge,          ///< more than two faces on an edge; element: edge's first face
  NonManifoldVertex,        ///< faces around the vertex form several fans; element: vertex
  InconsistentOrientation,  ///< two faces traverse an edge the same way; element: face
  NonOrientable,            ///< no consistent orientation exists; element: face
  UnreferencedVertex,       ///< no face uses it (a warning, not an error); element: vertex
};

template <>
struct EnumNames<DefectKind> {
  static constexpr const char* noun = "defect kind";
  static constexpr std::array<EnumName<DefectKind>, 10> names{{
      {DefectKind::NonFiniteCoordinate, "non-finite-coordinate"},
      {DefectKind::IndexOutOfRange, "index-out-of-range"},
      {DefectKind::RepeatedVertex, "repeated-vertex"},
      {DefectKind::ZeroAreaFace, "zero-area-face"},
      {DefectKind::DuplicateFace, "duplicate-face"},
      {DefectKind::NonManifoldEdge, "non-manifold-edge"},
      {DefectKind::NonManifoldVertex, "non-manifold-vertex"},
      {DefectKind::InconsistentOrientation, "inconsistent-orientation"},
      {DefectKind::NonOrientable, "non-orientable"},
      {DefectKind::UnreferencedVertex, "unreferenced-vertex"},
  }};
};

/// Short stable name of a defect kind, e.g. "non-manifold-edge" (its EnumNames row).
const char* defect_name(DefectKind kind);

/// One defect.
struct Defect {
  DefectKind kind;
  int element = -1;     ///< vertex or face index, as the kind says
  std::string message;  ///< e.g. "vertex 17 has coordinate nan"
};

/// Options of find_defects.
struct ValidationOptions {
  /// A face is degenerate when twice its area is at most this times its longest edge squared
  /// (the sine of its largest angle falls below it).
  double zero_area_tolerance = 1e-12;
  int max_defects_per_kind = 100;  ///< stop listing a kind after this many (the count goes on)
};

/// All defects found.
struct ValidationReport {
  std::vector<Defect> defects;                     ///< at most max_defects_per_kind of each kind
  std::vector<std::pair<DefectKind, int>> counts;  ///< total count of every kind found
  /// True when no defect other than UnreferencedVertex was found.
  bool ok() const;
  /// Total count of one kind of defect (0 when none was found).
  int count(DefectKind kind) const;
};

/// Lists every defect of the mesh.
ValidationReport find_defects(const Mesh& mesh, const ValidationOptions& options = {});

/// Throws on the first defect other than UnreferencedVertex.
/// \param context prefix of the message, usually the file name
/// \throw TopologyError for non-manifold, orientation and orientability defects
/// \throw InvalidInput for the others
void validate_mesh(const Mesh& mesh, const std::string& context,
                   const ValidationOptions& options = {});

/// Like validate_mesh, but on a report already computed.
void throw_first_defect(const ValidationReport& report, const std::string& context);

}  // namespace ricci
