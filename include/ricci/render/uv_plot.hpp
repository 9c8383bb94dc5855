#pragma once
/// \file
/// Pictures of a texture layout (the uv plane): every triangle filled with a colour map of its log
/// area distortion, thin edges, the seams thicker, the cones marked. PNG through an Image, SVG as
/// text.

#include <string>

#include <Eigen/Core>

#include "ricci/mesh/mesh.hpp"
#include "ricci/render/image.hpp"

namespace ricci {

/// ln(A_uv / A_3d) per face, both areas normalised to total 1 (the 3D areas by their sum, the
/// texture areas by the sum of their absolute values). Faces with zero texture area get -inf.
/// \return #F values; a flipped face (negative signed texture area) gets the value of |A_uv|
/// \throw InvalidInput as check_uv_layout, or when the 3D area or the texture area is zero
Eigen::VectorXd log_area_ratio(const Mesh& mesh, const Triangles& uv_triangles,
                               const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv);

/// The diverging colour map of the layout plots: blue at t = -1, white at 0, red at +1
/// (t clamped to [-1, 1]).
Rgb diverging_colour(double t);

/// Options of the layout plots.
struct UvPlotOptions {
  int width = 1024;   ///< pixels (SVG: px)
  int height = 1024;  ///< pixels, the colour bar included
  /// Colour range: +-min(max_log_area, the largest |ln(A_uv / A_3d)|) maps onto blue..red.
  double max_log_area = 2;
  /// Thin edges around every face, when faces are large enough to show them (on average at least
  /// 20 square pixels); SVG always has them.
  bool draw_edges = true;
  double edge_width = 0.4;             ///< pixels
  double seam_width = 1.8;             ///< pixels
  bool mark_cones = true;              ///< red dots at every texture copy of a cone
  double cone_tolerance = 1e-6;        ///< see analyse_uv_chart
  bool colour_bar = true;              ///< a horizontal colour bar with its range under the layout
  Rgb flipped_colour{1.0, 0.85, 0.0};  ///< faces whose texture triangle is flipped
};

/// What the layout plots return besides the picture.
struct UvPlotInfo {
  double colour_range = 0;  ///< the |ln(A_uv / A_3d)| mapped onto full blue or red
  double log_area_min = 0, log_area_max = 0;  ///< over the faces with a finite value
  int flipped_faces = 0;
  int seam_halfedges = 0;
  int cones = 0;
};

/// The layout as a raster picture (the uv bounding box fitted into the picture, v upwards).
/// \throw InvalidInput as log_area_ratio, on a picture size outside [1, 16384], or non-finite uv
Image plot_uv_layout(const Mesh& mesh, const Triangles& uv_triangles,
                     const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv,
                     const UvPlotOptions& options = {}, UvPlotInfo* info = nullptr);

/// The same picture as SVG text: one `<path>` element per face (fill and edge stroke together),
/// then one for all seams, one for all cone dots (when there are cones) and the colour bar's.
/// \throw InvalidInput as plot_uv_layout
std::string plot_uv_layout_svg(const Mesh& mesh, const Triangles& uv_triangles,
                               const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv,
                               const UvPlotOptions& options = {}, UvPlotInfo* info = nullptr);

}  // namespace ricci
