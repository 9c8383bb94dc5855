#pragma once
/// \file
/// Private to the mesh readers: the file's faces as Polygons (ricci/mesh/polygons.hpp) over the
/// triangles read_mesh returns, after triangulation and, when asked, after repair.

#include <vector>

#include "ricci/mesh/mesh.hpp"
#include "ricci/mesh/polygons.hpp"

namespace ricci::io_detail {

/// The file's faces over the triangles read_mesh returns. A face keeps its polygon when all its
/// triangles are returned, none or all of them reversed by repair (then its corners are listed
/// in reverse order: the same face turned over), and each of its corners is one vertex in all of
/// them (repair may have split a vertex between its triangles); otherwise each of its triangles
/// left is a face of its own. Empty when no face of more than three corners is kept.
/// \param polygon_start #P + 1 offsets into the file's corners (RawMesh::polygon_start)
/// \param polygon_of_triangle per triangle of the triangulation: its file face
/// \param triangle_corners 3 per triangle of the triangulation: the file corner (index into the
///        file's corners) at each of its corners
/// \param triangles #F by 3: the triangles returned (after repair the repaired ones)
/// \param face_map #F: the triangulation's triangle each returned triangle comes from, ascending
///        (RepairResult::face_map); empty: the identity
/// \param face_flipped #F: 1 where repair reversed the triangle (corners 1 and 2 exchanged);
///        empty: none
Polygons file_polygons(const std::vector<int>& polygon_start,
                       const std::vector<int>& polygon_of_triangle,
                       const std::vector<int>& triangle_corners, const Triangles& triangles,
                       const std::vector<int>& face_map, const std::vector<char>& face_flipped);

}  // namespace ricci::io_detail
