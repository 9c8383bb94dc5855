#pragma once
/// \file
/// Reading OBJ files with texture coordinates (`v`, `vt`, `f v/vt`): what `ricci param` writes
/// and `ricci render` draws. ricci::read_mesh reads the geometry only and ignores `vt`.

#include <string>

#include <Eigen/Core>

#include "ricci/mesh/mesh.hpp"

namespace ricci {

/// A mesh with per-corner texture coordinates.
struct TexturedMesh {
  Mesh mesh;  ///< positions (#V by 3, every `v` of the file) and triangles (#F by 3)
  Triangles
      uv_triangles;  ///< #F by 3 indices into uv: corner c of face f has uv(uv_triangles(f, c))
  /// #UV by 2, every `vt` of the file (u, v); for homogeneous coordinates (see uv_weights)
  /// (u / w, v / w), the texture coordinates at the corners.
  Eigen::Matrix<double, Eigen::Dynamic, 2> uv;
  /// #UV homogeneous weights when every `vt` has a third component w and every w is positive
  /// (`vt u v w` as `ricci param --faces refinement` writes it: (u, v, w) interpolated linearly
  /// and divided by w give the texture coordinates, a projective map per face); empty otherwise
  /// (the third component of ordinary files, often 0, is ignored).
  Eigen::VectorXd uv_weights;
  int polygons_triangulated = 0;  ///< faces with more than three corners, split as a fan
};

/// Reads an OBJ file whose every face corner names a texture coordinate (`f v/vt` or
/// `f v/vt/vn`; negative indices count back from the last element read). Texture coordinates
/// with a positive third component on every `vt` are read as homogeneous (uv_weights). Polygons are
/// split as a fan from their first corner; normals, groups, materials and smoothing groups are
/// ignored. Vertices are kept in file order, referenced or not. \throw IoError "path: line N: ..."
/// when the file is missing, empty of faces, or a statement is
///        malformed (a corner without a texture index, a bad number, free-form geometry, an
///        unknown statement, a coordinate that is not finite)
/// \throw InvalidInput "path: line N: ..." when a face refers to a vertex or texture coordinate
///        that the file has not defined
TexturedMesh read_textured_obj(const std::string& path);

}  // namespace ricci
