#pragma once
// Private to the param module: a mesh laid out in its own 3D shape (patches grown face by face
// across edges, none overlapping another), and a layout split into pieces in none of which two
// faces overlap. parameterize_components() lays out components this way when the flow fails or
// distorts them; charts.cpp lays out the faces its charts give up; both split overlapping
// layouts into pieces.

#include <vector>

#include <Eigen/Core>

#include "ricci/mesh/mesh.hpp"
#include "ricci/mesh/polygons.hpp"
#include "ricci/param/parameterize.hpp"

namespace ricci::param_detail {

using Points = Eigen::Matrix<double, Eigen::Dynamic, 2>;

/// A mesh developed in its own 3D shape, as patches: each patch grows breadth first from a
/// seed face, every new face laid out across an edge of a face already in the patch (so with its
/// exact 3D shape) unless it would overlap a face of the patch (exact test); faces left over
/// seed further patches. One patch is an unfolding of the whole mesh: cut wherever its faces
/// were not glued, which includes every curved vertex's wedge of faces unless it closes up, and
/// no distortion at all. A polygon (of polygons, when not empty) joins a patch whole: its other
/// triangles are developed across its diagonals, and it joins when none of them overlaps the
/// patch, so that no patch boundary runs inside a polygon.
struct PatchLayout {
  Triangles triangles;              ///< #F by 3: cut-mesh vertex of each corner
  std::vector<int> vertex;          ///< per cut-mesh vertex: the mesh vertex it copies
  Points layout;                    ///< per cut-mesh vertex
  std::vector<int> face_patch;      ///< #F
  std::vector<char> is_glued_edge;  ///< #E: its two faces are laid out side by side
  int num_patches = 0;
};

/// \pre mesh is manifold and oriented (build_topology succeeds)
PatchLayout develop_patches(const Mesh& mesh, const Polygons& polygons = {});

/// The ParamResult of a mesh that unfolded into one patch (ComponentMethod::Unfolded), with its
/// polygons (when not empty) written from corners whose fans are sound (ParamResult::polygons).
ParamResult unfolded_result(const Mesh& mesh, const PatchLayout& patches,
                            const Polygons& polygons = {});

/// A layout cut into pieces in none of which two faces overlap: each piece grows breadth first
/// from a seed face across the layout's shared edges, a face joining only when it overlaps no
/// face of the piece (exact test). A polygon (triangle_polygon, when not empty: #F polygon
/// indices) joins whole, when none of its triangles overlaps the piece. Returns the piece of each
/// face; `count` pieces.
std::vector<int> embedded_pieces(const Points& uv, const Triangles& triangles, int& count,
                                 const std::vector<int>& triangle_polygon = {});

/// The vertices of a layout split into charts: the corners of one layout vertex stay one vertex
/// across the layout's edges between faces of the same chart, and each class of corners becomes
/// a vertex of its own (a chart touching itself at a vertex gets a copy per fan).
/// \param triangles #F by 3 layout vertex of each corner, rewritten to the new vertices
/// \param face_chart #F: chart of each face
/// \return per new vertex, the layout vertex it copies
std::vector<int> split_at_charts(Triangles& triangles, int num_layout_vertices,
                                 const std::vector<int>& face_chart);

/// ParamResult::uv from the layout: the unit square, aspect ratio kept (as the pipeline does).
void fit_unit_square(ParamResult& r);

/// Per edge of t: 1 where its two faces hold the same cut-mesh vertices at both its ends (laid
/// out side by side), 0 on the boundary and where the layout cuts it.
std::vector<char> glued_edges(const Topology& t, const Triangles& cut_triangles);

/// The ParamResult of a layout made without the pipeline on the mesh's own faces (unfolded,
/// charts): converged, the mesh and its vertices as they are, the cut (every interior edge the
/// layout does not glue) with its 3D length, the cut mesh and layout, the polygons written from
/// sound fans, the distortion measured on them, uv fitted into the unit square. No cones.
/// \param t, lengths the mesh's topology and 3D edge lengths
/// \param triangles #F by 3 indices into layout; vertex: per layout vertex, its mesh vertex
ParamResult own_layout_result(const Mesh& mesh, const Topology& t, const Eigen::VectorXd& lengths,
                              const Triangles& triangles, const std::vector<int>& vertex,
                              const Points& layout, const Polygons& polygons);

}  // namespace ricci::param_detail
