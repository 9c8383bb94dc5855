// Convergence plots of synthetic histories: sizes, files, and what they refuse.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "render_test_support.hpp"
#include "ricci/errors.hpp"
#include "ricci/render/convergence_plot.hpp"

namespace ricci {
namespace {

/// Newton-like (quadratic) and gradient-like (linear) error sequences.
std::vector<ConvergenceCurve> synthetic_curves() {
  std::vector<IterationRecord> newton(6);
  const double errors[] = {0.3, 2e-2, 1e-4, 3e-9, 5e-15, 0.0};  // the last exactly converged
  for (int i = 0; i < 6; ++i) {
    newton[i].iteration = i;
    newton[i].max_error = errors[i];
  }
  std::vector<IterationRecord> gradient(800);
  for (int i = 0; i < 800; ++i) {
    gradient[i].iteration = i;
    gradient[i].max_error = 0.3 * std::pow(0.96, i);
  }
  return {convergence_curve("Newton", newton, {0.1, 0.3, 0.8}),
          convergence_curve("gradient flow", gradient, {0.8, 0.1, 0.1})};
}

TEST(ConvergencePlot, CurveFromHistory) {
  const std::vector<ConvergenceCurve> curves = synthetic_curves();
  EXPECT_EQ(curves[0].label, "Newton");
  ASSERT_EQ(curves[0].max_error.size(), 6u);
  EXPECT_EQ(curves[0].max_error[3], 3e-9);
  EXPECT_TRUE(curves[0].markers);
  EXPECT_FALSE(curves[1].markers);
}

TEST(ConvergencePlot, PngHasTheRequestedSize) {
  ConvergencePlotOptions options;
  options.width = 640;
  options.height = 480;
  options.title = "synthetic";
  options.tolerance = 1e-12;
  for (IterationAxis axis : {IterationAxis::Auto, IterationAxis::Linear, IterationAxis::Log}) {
    options.iteration_axis = axis;
    const Image image = plot_convergence(synthetic_curves(), options);
    EXPECT_EQ(image.width, 640);
    EXPECT_EQ(image.height, 480);
    const auto path = testing::render_tmp_dir() / "convergence.png";
    write_png(path.string(), image);
    const Image back = read_png(path.string());
    EXPECT_EQ(back.width, 640);
    EXPECT_EQ(back.height, 480);
    // Something was drawn in both curve colours: count strongly blue and strongly red pixels.
    int blue = 0, red = 0;
    for (std::uint32_t p : back.pixels) {
      const Rgb c = unpack_rgb(p);
      blue += c.b > 0.6 && c.r < 0.3;
      red += c.r > 0.6 && c.b < 0.3 && c.g < 0.3;
    }
    EXPECT_GT(blue, 100);
    EXPECT_GT(red, 300);
  }
}

TEST(ConvergencePlot, SvgIsADocument) {
  const std::string svg = plot_convergence_svg(synthetic_curves());
  EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("width=\"900px\""), std::string::npos);
  const std::size_t end = svg.find("</svg>");
  ASSERT_NE(end, std::string::npos);
  EXPECT_EQ(svg.find_first_not_of(" \n", end + 6), std::string::npos);
}

TEST(ConvergencePlot, RefusesNothingToPlot) {
  ConvergenceCurve empty;
  empty.max_error = {0.0, -1.0, std::numeric_limits<double>::quiet_NaN()};
  EXPECT_THROW(plot_convergence({empty}), InvalidInput);
  EXPECT_THROW(plot_convergence({}), InvalidInput);
  ConvergencePlotOptions tiny;
  tiny.width = 10;
  EXPECT_THROW(plot_convergence(synthetic_curves(), tiny), InvalidInput);
}

}  // namespace
}  // namespace ricci
