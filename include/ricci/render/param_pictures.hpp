#pragma once
/// \file
/// The pictures of a parameterization, written into one folder (`ricci param --pictures`):
/// the textured surface, the texture layout with its area distortion, and the flow's convergence
/// next to the gradient flow's on the same target.

#include <string>
#include <vector>

#include "ricci/param/parameterize.hpp"
#include "ricci/render/convergence_plot.hpp"
#include "ricci/render/render_mesh.hpp"
#include "ricci/render/uv_plot.hpp"
#include "ricci/render/web_viewer.hpp"

namespace ricci {

/// Options of write_parameterization_pictures.
struct ParamPicturesOptions {
  RenderOptions render;                ///< render.png
  UvPlotOptions uv;                    ///< uv.svg and uv.png
  ConvergencePlotOptions convergence;  ///< convergence.png and convergence.svg
  /// The gradient flow runs for the convergence plot only on meshes with fewer vertices.
  int gradient_max_vertices = 20000;
  int gradient_max_iterations = 5000;  ///< its iteration limit
  double gradient_max_seconds = 20;    ///< and its time limit (seconds of wall time)
  double gradient_tolerance = 1e-12;   ///< it stops there if it gets that far
  /// view.html, the interactive viewer (web_viewer.hpp), when this build has three.js
  /// (web_viewer_available); left out silently otherwise.
  bool web_viewer = true;
  WebViewerOptions viewer;  ///< its options (its title: empty gives one from the result)
};

/// What write_parameterization_pictures wrote.
struct ParamPicturesResult {
  std::vector<std::string> files;  ///< the paths written, in order
  bool gradient_ran = false;       ///< the convergence plot has a gradient flow curve
  int gradient_iterations = 0;
  double gradient_max_error = 0;  ///< its final max |K-bar - K|
  std::string gradient_status;    ///< flow_status_name of how it stopped
};

/// Writes render.png, uv.svg, uv.png, convergence.png, convergence.svg and view.html into
/// `folder` (created when missing), each atomically. The convergence plot is left out when every
/// error of the flows is exactly 0 (nothing to draw on a logarithmic axis); view.html as
/// options.web_viewer says.
/// \pre result.converged and result describes one connected component (what parameterize makes)
/// \throw InvalidInput when the result has no layout
/// \throw IoError naming the folder or file when it cannot be written
ParamPicturesResult write_parameterization_pictures(const std::string& folder,
                                                    const MeshParamResult& result,
                                                    const ParamPicturesOptions& options = {});

}  // namespace ricci
