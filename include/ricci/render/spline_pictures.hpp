#pragma once
/// \file
/// The pictures of a manifold spline, written into one folder (`ricci spline --pictures`; the
/// three stages of the tutorial's figures 14, 16 and 18): the domain mesh with the
/// parameterization's checkerboard, the control net as a wireframe over faint faces, and the
/// spline surface with the same checkerboard, all three from one camera; and the flat layout of
/// the domain with its seams and cones.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "ricci/render/render_mesh.hpp"
#include "ricci/render/uv_plot.hpp"
#include "ricci/spline/manifold_spline.hpp"

namespace ricci {

/// Options of write_spline_pictures.
struct SplinePicturesOptions {
  /// domain.png, control_net.png and surface.png: size, view, checker, colours. Its camera, when
  /// set, is used for all three; otherwise fit_camera frames the domain, the control net and the
  /// surface together.
  RenderOptions render;
  UvPlotOptions uv;                ///< layout.png
  Rgb net_face{0.94, 0.94, 0.91};  ///< the control net's faces (shaded, no checker)
  Rgb net_edge{0.10, 0.22, 0.60};  ///< the control net's edges
  /// Pixels; 0: an eighth of the net's mean edge length on the picture, within [0.2, 1.2] (a
  /// dense net stays see-through).
  double net_edge_width = 0;
  bool smooth_surface = true;  ///< surface.png with interpolated vertex normals
};

/// What write_spline_pictures wrote.
struct SplinePicturesResult {
  std::vector<std::string> files;  ///< the paths written, in order
  Camera camera;                   ///< the camera of the three renders
  int domain_visible_faces = 0;    ///< faces that won a z-buffer sample, per render
  int net_visible_faces = 0;
  int surface_visible_faces = 0;
  int surface_cones = 0;  ///< cones found on the surface's texture (those of the domain)
};

/// Texture coordinates of a spline surface.
struct SplineSurfaceTexture {
  Triangles uv_triangles;                       ///< #T by 3 indices into uv, one per corner
  Eigen::Matrix<double, Eigen::Dynamic, 2> uv;  ///< 3 #T by 2
};

/// The parameterization's texture carried onto the spline surface: every corner of a surface
/// triangle gets ParamResult::uv interpolated at the corner's place in the domain face the
/// triangle subdivides. Points on a domain edge get bitwise the same coordinates from both faces
/// where the edge is not cut, so analyse_uv_chart finds the domain's seams and cones again.
/// \pre result.converged
/// \throw InvalidInput when the result has no surface or its arrays do not match
SplineSurfaceTexture spline_surface_texture(const SplineResult& result);

/// Writes domain.png, control_net.png, surface.png and layout.png into `folder` (created when
/// missing), each atomically.
/// \pre result.converged
/// \throw InvalidInput when the result has no surface (did not converge) or as
///        render_textured_mesh and plot_uv_layout
/// \throw IoError naming the folder or file when it cannot be written
SplinePicturesResult write_spline_pictures(const std::string& folder, const SplineResult& result,
                                           const SplinePicturesOptions& options = {});

}  // namespace ricci
