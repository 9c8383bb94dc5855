#pragma once
/// \file
/// Convergence plots of the Ricci flow (the tutorial's figure 7): max |K-bar - K| against the
/// iteration on a logarithmic axis, one curve per solver.

#include <string>
#include <vector>

#include "ricci/flow/ricci_flow.hpp"
#include "ricci/render/image.hpp"

namespace ricci {

/// One curve: the error after each iteration, iteration 0 first.
struct ConvergenceCurve {
  std::string label;              ///< legend text, e.g. "Newton"
  std::vector<double> max_error;  ///< per iteration; values <= 0 or not finite are left out
  Rgb colour{0.12, 0.35, 0.75};   ///< line colour
  bool markers = false;           ///< a dot at every iteration (short curves)
};

/// The curve of a flow's history (IterationRecord::max_error per iteration); markers when it has
/// at most 60 iterations.
ConvergenceCurve convergence_curve(const std::string& label,
                                   const std::vector<IterationRecord>& history, const Rgb& colour);

/// Scale of the iteration axis.
enum class IterationAxis {
  Auto,    ///< Log when the longest curve has over 10 times the iterations of the shortest and
           ///< more than 100 (Newton next to the gradient flow), else Linear
  Linear,  ///< iterations 0, 1, 2, ...
  Log,     ///< log10(iteration + 1)
};

/// Options of the convergence plots.
struct ConvergencePlotOptions {
  int width = 900;       ///< pixels (SVG: px)
  int height = 600;      ///< pixels
  std::string title;     ///< above the plot; empty: none
  double tolerance = 0;  ///< > 0: a dashed horizontal line at the flow's tolerance
  IterationAxis iteration_axis = IterationAxis::Auto;
  std::string x_label = "iteration";
  std::string y_label = "max |K\xCC\x84 \xE2\x88\x92 K|  (rad)";  ///< K with a macron, minus sign
};

/// The plot as a raster picture.
/// \throw InvalidInput when no curve has a positive finite value, or on a picture size outside
///        [64, 16384] x [64, 16384]
Image plot_convergence(const std::vector<ConvergenceCurve>& curves,
                       const ConvergencePlotOptions& options = {});

/// The same plot as SVG text. \throw InvalidInput as plot_convergence
std::string plot_convergence_svg(const std::vector<ConvergenceCurve>& curves,
                                 const ConvergencePlotOptions& options = {});

}  // namespace ricci
