#pragma once
/// \file
/// A triangle mesh with per-corner texture coordinates: what `ricci param` writes (see
/// ricci/param/output_mesh.hpp), what read_textured_obj reads back and what write_mesh writes.

#include <Eigen/Core>

#include "ricci/mesh/mesh.hpp"
#include "ricci/mesh/polygons.hpp"

namespace ricci {

/// A mesh with per-corner texture coordinates. Corners that share a uv index share a texture
/// coordinate; a seam is an edge whose two faces give its ends different uv indices. A mesh
/// without texture coordinates has uv_triangles and uv empty (0 rows).
struct TexturedMesh {
  Mesh mesh = {};  ///< positions (#V by 3, e.g. every `v` of an OBJ file) and triangles (#F by 3)
  /// #F by 3 indices into uv: corner c of face f has uv(uv_triangles(f, c)).
  Triangles uv_triangles = {};
  /// #UV by 2, e.g. every `vt` of an OBJ file (u, v); for homogeneous coordinates (see
  /// uv_weights) (u / w, v / w), the texture coordinates at the corners.
  Eigen::Matrix<double, Eigen::Dynamic, 2> uv = {};
  /// #UV homogeneous weights when every `vt` has a third component w and every w is positive
  /// (`vt u v w` as `ricci param --faces refinement` writes it: (u, v, w) interpolated linearly
  /// and divided by w give the texture coordinates, a projective map per face); empty otherwise
  /// (the third component of ordinary files, often 0, is ignored).
  Eigen::VectorXd uv_weights = {};
  /// Faces of the file read with more than three corners, split as a fan (readers only).
  int polygons_triangulated = 0;
  /// The faces as polygons over the triangles (ricci/mesh/polygons.hpp): write_mesh writes each
  /// polygon as one face (OBJ `f v/vt v/vt v/vt v/vt`, OFF, PLY) with each corner's vertex and uv
  /// row taken from the triangle corner it names; empty: every triangle is a face. STL and glTF
  /// hold triangles only and write the triangles.
  Polygons polygons = {};

  /// True when the mesh carries texture coordinates (write_mesh checks that uv_triangles then
  /// has a row per face).
  bool has_uv() const { return uv_triangles.rows() > 0 || uv.rows() > 0; }
};

}  // namespace ricci
