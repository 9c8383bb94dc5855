#pragma once
/// \file
/// Private to write_mesh: one writer per format that holds positions and triangles only (OBJ's
/// writer is the public write_obj). Each writes atomically (write_file_atomically); write_mesh has
/// checked the indices and coordinates before.

#include <Eigen/Core>
#include <string>

#include "ricci/mesh/mesh.hpp"

namespace ricci::io_detail {

/// The checks of the writers before anything is written: every vertex index of a face in range;
/// with uv_triangles (not null) one row per face, every uv index in range, every uv row finite.
/// \throw InvalidInput "function: path: ..." naming the face and corner, or the uv row
void check_faces(const std::string& function, const std::string& path, const Mesh& mesh,
                 const Triangles* uv_triangles, const Eigen::Ref<const Eigen::MatrixXd>& uv);

/// ASCII OFF: `OFF`, the counts, `x y z` per vertex (17 significant digits: the doubles read back
/// exactly), `3 a b c` per face (0-based).
void write_off(const std::string& path, const Mesh& mesh);

/// Binary little-endian PLY: double x, y, z per vertex and a uchar-counted int list per face.
void write_ply(const std::string& path, const Mesh& mesh);

/// Binary STL: per face its unit normal (zero for a degenerate face) and three corners, as float;
/// the format has no shared vertices.
void write_stl(const std::string& path, const Mesh& mesh);

}  // namespace ricci::io_detail
