#pragma once
/// \file
/// Polygonal faces over a triangle mesh. Every computation of ricci runs on triangles, so
/// read_mesh splits a file's faces of more than three corners into triangles; Polygons keeps
/// which triangles make up each face of the file and its corners in order, so that what the
/// computation made of the triangles can be written back on the file's own faces (ricci param's
/// OBJ: `f v/vt v/vt v/vt v/vt`). The edges a polygon's triangulation added (its diagonals) are
/// no edges of the file: the cut of a parameterization must not run along them
/// (polygon_diagonals, CutGraphOptions::uncut_edges).

#include <string>
#include <vector>

#include "ricci/mesh/mesh.hpp"
#include "ricci/mesh/topology.hpp"

namespace ricci {

/// The faces of a polygon mesh over its triangles. Empty (no polygon at all) stands for a mesh
/// whose every triangle is a face of its own.
struct Polygons {
  /// #F: the polygon each triangle of the mesh belongs to (0 .. #P - 1). A polygon of n corners
  /// has n - 2 triangles.
  std::vector<int> triangle_polygon;
  /// #P + 1 offsets into corners (empty when there is no polygon): polygon p has the corners
  /// corners[corner_start[p] .. corner_start[p + 1]).
  std::vector<int> corner_start;
  /// The corners of every polygon in order around it (counter-clockwise, as its triangles), each
  /// named by a corner 3 t + k of one of its triangles t: the corner's vertex is triangles(t, k)
  /// and, in a mesh with texture coordinates, its uv row is uv_triangles(t, k).
  std::vector<int> corners;

  /// True when there is no polygon (every triangle a face of its own).
  bool empty() const { return corner_start.size() < 2; }
  /// #P.
  int num_polygons() const { return empty() ? 0 : static_cast<int>(corner_start.size()) - 1; }
  /// The number of corners of polygon p.
  int size(int p) const { return corner_start[p + 1] - corner_start[p]; }
};

/// Checks that polygons describes faces over `triangles`: one polygon index per triangle, corner
/// offsets from 0 to corners.size(), at least three corners per polygon and n - 2 triangles for n
/// corners, every corner a corner of a triangle of its polygon, and every triangle's vertices
/// corners of its polygon. An empty Polygons passes.
/// \throw InvalidInput "context: ..." naming the polygon, corner or triangle
void check_polygons(const Polygons& polygons, const Triangles& triangles,
                    const std::string& context);

/// The fan of every polygon from its first corner, polygon after polygon: rows (c_0, c_i,
/// c_i+1) for i = 1 .. n - 2, each corner c given as corner_values(t, k) for c = 3 t + k. With
/// the mesh's triangles these are the triangles an OBJ reader makes of the written polygons;
/// with uv_triangles their texture coordinates.
/// \param corner_values #F by 3 (the mesh's triangles, or uv_triangles)
/// \pre polygons is not empty and passes check_polygons
Triangles polygon_fans(const Polygons& polygons, const Triangles& corner_values);

/// #E flags: 1 for the interior edges whose two triangles belong to one polygon (its diagonals,
/// which the file does not have). All 0 when polygons is empty.
/// \pre polygons passes check_polygons for topology.triangles
std::vector<char> polygon_diagonals(const Topology& topology, const Polygons& polygons);

/// The polygons of a subset of the triangles, in the subset's numbering: triangle i of the
/// subset is triangle faces[i] of the mesh. Polygons are kept in their order; a polygon some of
/// whose triangles are not in the subset is left as its triangles there (one polygon each).
/// Empty when polygons is empty or no polygon of more than three corners is left.
Polygons polygons_of_faces(const Polygons& polygons, const std::vector<int>& faces);

}  // namespace ricci
