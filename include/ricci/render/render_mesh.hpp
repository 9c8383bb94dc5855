#pragma once
/// \file
/// Pictures of a textured mesh without a window: a small software rasteriser (orthographic
/// camera, per-sample z-buffer, supersampling) draws the surface with a checkerboard texture and
/// Lambert shading into an ARGB32 image; Cairo then draws the seams and the cones on top. The
/// checker squares stay square on the surface exactly where the parameterization is conformal.

#include <optional>

#include <Eigen/Core>

#include "ricci/mesh/mesh.hpp"
#include "ricci/render/image.hpp"

namespace ricci {

/// An orthographic camera: world point p goes to pixel (x, y) = (scale (p - centre) . right +
/// width / 2, height / 2 - scale (p - centre) . up) of the final picture; depth (p - centre) .
/// view grows towards the camera.
struct Camera {
  Eigen::Vector3d view = Eigen::Vector3d::UnitZ();   ///< unit vector from the scene to the camera
  Eigen::Vector3d up = Eigen::Vector3d::UnitY();     ///< unit screen up, orthogonal to view
  Eigen::Vector3d right = Eigen::Vector3d::UnitX();  ///< unit screen right, up x view
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  ///< world point at the picture's centre
  double scale = 1;                                  ///< pixels per world unit
  int width = 1, height = 1;                         ///< picture size, pixels

  /// Pixel coordinates of a world point (pixel (i, j) covers [i, i + 1) x [j, j + 1)).
  Eigen::Vector2d project(const Eigen::Vector3d& point) const;
  /// Depth of a world point: larger is nearer to the camera.
  double depth(const Eigen::Vector3d& point) const { return (point - centre).dot(view); }
};

/// The camera direction of an automatic view, from the mesh's bounding box: a flat mesh (least
/// extent below 5% of the largest) is seen straight along its least-extent axis, from the side
/// its faces mostly face; a flattish one (below 35%) from 40 degrees above the plane of its two
/// larger axes, the longest horizontal; anything else in a 3/4 view with +y up (azimuth 30
/// degrees from +z, elevation 20 degrees).
/// \param up receives the matching screen up direction (unit, orthogonal to the result)
/// \throw InvalidInput when the mesh has no faces or a coordinate is not finite
Eigen::Vector3d automatic_view(const Mesh& mesh, Eigen::Vector3d* up = nullptr);

/// Options of render_textured_mesh.
struct RenderOptions {
  int width = 1024;   ///< picture width, pixels
  int height = 1024;  ///< picture height, pixels
  /// Direction from the scene towards the camera (any length); zero: automatic_view.
  Eigen::Vector3d view = Eigen::Vector3d::Zero();
  /// Screen up direction (made orthogonal to the view); zero: automatic_view's with an automatic
  /// view, else +y (-z looking from +y, +z looking from -y).
  Eigen::Vector3d up = Eigen::Vector3d::Zero();
  int checker = 16;  ///< checker squares per unit of texture coordinate
  /// z-buffer samples per pixel along each axis (anti-aliasing), in [1, 8]; lowered for large
  /// pictures so that width * height * supersampling^2 stays within 2^27 samples.
  int supersampling = 3;
  /// Shade with area-weighted vertex normals interpolated over each face instead of the face
  /// normal (hides the facets of coarse meshes; the checker is the same).
  bool smooth_shading = false;
  double margin = 0.05;          ///< fraction of the picture's smaller side left around the mesh
  bool draw_seams = true;        ///< dark lines along the texture seams (UvChart)
  bool mark_cones = true;        ///< red dots on the cones (UvChart)
  double cone_tolerance = 1e-6;  ///< see analyse_uv_chart
  Rgb background{1, 1, 1};
  Rgb checker_light{0.95, 0.95, 0.93};  ///< squares where floor(u N) + floor(v N) is even
  Rgb checker_dark{0.20, 0.42, 0.78};   ///< squares where it is odd
  Rgb seam_colour{0.08, 0.08, 0.08};
  Rgb cone_colour{0.90, 0.05, 0.05};
  double seam_width = 1.6;  ///< pixels
  double cone_radius = 0;   ///< pixels; 0: max(3, picture's smaller side / 140)
  /// Every mesh edge as a line where visible (a wireframe over the faces), under the seams.
  bool draw_edges = false;
  Rgb edge_colour{0.15, 0.15, 0.15};
  double edge_width = 0.8;  ///< pixels
  /// #UV homogeneous weights w > 0 (TexturedMesh::uv_weights): each sample's texture
  /// coordinates are (sum b_i w_i uv_i) / (sum b_i w_i) over the face's corners i with the
  /// sample's barycentric coordinates b_i (projective interpolation, exact for the common
  /// refinement's map); empty: linear interpolation.
  Eigen::VectorXd uv_weights;
  /// Use this camera as it is (view, up, right, centre, scale; its width and height are replaced
  /// by the picture's) instead of fitting one to the mesh: several pictures from one viewpoint
  /// (fit_camera frames several meshes at once). view, up and margin are then ignored.
  std::optional<Camera> camera;
};

/// The camera render_textured_mesh fits to a mesh (options.camera ignored): view and up as the
/// options say (automatic_view of `mesh` by default), centre and scale such that the used
/// vertices of `mesh` and every row of `also_frame` fill the picture but for options.margin.
/// \param also_frame #P by 3 further world points to keep in the picture (e.g. other meshes)
/// 	hrow InvalidInput on a mesh without faces, non-finite coordinates, a picture size outside
///        [1, 16384], a margin outside [0, 0.5), or a bad view or up direction
Camera fit_camera(const Mesh& mesh, const RenderOptions& options,
                  const Positions& also_frame = Positions());

/// What render_textured_mesh returns.
struct RenderResult {
  Image image;
  Camera camera;          ///< where every world point landed
  int visible_faces = 0;  ///< faces that won at least one z-buffer sample
  int seam_edges = 0;     ///< mesh edges on seams (drawn where visible)
  int edges = 0;          ///< with draw_edges: mesh edges (drawn where visible)
  int cones = 0;          ///< cone vertices (marked where visible)
  int visible_cones = 0;  ///< cones drawn
};

/// Renders a textured mesh: checkerboard with N = options.checker squares per texture unit
/// (colour from the parity of floor(u N) + floor(v N), u and v interpolated linearly over each
/// face, or projectively with options.uv_weights), two-sided Lambert shading from the face normal
/// (or interpolated vertex normals) with a light above-left of the camera, back faces darker; the
/// nearest surface wins every sample of the z-buffer. The mesh fills the picture but for the
/// margin. \param uv_triangles #F by 3 indices into uv (per-corner texture coordinates) \param uv
/// #UV by 2 texture coordinates \throw InvalidInput on a mismatch of the arrays (see
/// check_uv_layout), a mesh without faces,
///        non-finite coordinates, a picture size outside [1, 16384], checker < 1, supersampling
///        outside [1, 8], a view direction that is zero after normalisation or parallel to up,
///        or a given camera whose axes or scale are not finite or whose scale is not positive
RenderResult render_textured_mesh(const Mesh& mesh, const Triangles& uv_triangles,
                                  const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv,
                                  const RenderOptions& options = {});

}  // namespace ricci
