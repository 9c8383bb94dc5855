// Texture layout plots: the log area ratio, the colour map, the PNG and the SVG.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "render_test_support.hpp"
#include "ricci/errors.hpp"
#include "ricci/render/uv_plot.hpp"

namespace ricci {
namespace {

using UV = Eigen::Matrix<double, Eigen::Dynamic, 2>;

/// The unit square as two triangles whose texture triangles have areas 0.5 s0 and 0.5 s1.
struct Square {
  Mesh mesh;
  Triangles uv_triangles;
  UV uv;
};

Square stretched_square(double s0, double s1) {
  Square q;
  q.mesh.positions.resize(4, 3);
  q.mesh.positions << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  q.mesh.triangles.resize(2, 3);
  q.mesh.triangles << 0, 1, 2, 0, 2, 3;
  q.uv_triangles.resize(2, 3);
  q.uv_triangles << 0, 1, 2, 3, 4, 5;
  q.uv.resize(6, 2);
  q.uv << 0, 0, s0, 0, s0, 1, 0, 0, 1, 1, 0, s1;  // second triangle: (0,0) (1,1) (0,s1)
  return q;
}

TEST(UvPlot, LogAreaRatioOfAnIsometryIsZero) {
  const auto g = testing::grid_with_uv(6);
  EXPECT_LT(log_area_ratio(g.mesh, g.uv_triangles, g.uv * 3.0).cwiseAbs().maxCoeff(), 1e-14);
}

TEST(UvPlot, LogAreaRatioAfterNormalisation) {
  // 3D areas 0.5 and 0.5; texture areas 0.5 * 3 and 0.5 * 1, i.e. 3/4 and 1/4 of the total.
  const Square q = stretched_square(3.0, 1.0);
  const Eigen::VectorXd r = log_area_ratio(q.mesh, q.uv_triangles, q.uv);
  EXPECT_NEAR(r[0], std::log(0.75 / 0.5), 1e-15);
  EXPECT_NEAR(r[1], std::log(0.25 / 0.5), 1e-15);
}

TEST(UvPlot, DivergingColourMap) {
  const Rgb white = diverging_colour(0), blue = diverging_colour(-1), red = diverging_colour(5);
  EXPECT_EQ(pack_rgb(white), pack_rgb({1, 1, 1}));
  EXPECT_GT(blue.b, blue.r + 0.3);
  EXPECT_GT(red.r, red.b + 0.3);
  EXPECT_EQ(pack_rgb(red), pack_rgb(diverging_colour(1)));  // clamped
}

TEST(UvPlot, PngColoursFacesByTheirDistortion) {
  const Square q = stretched_square(3.0, 1.0);
  UvPlotOptions options;
  options.width = 300;
  options.height = 200;
  UvPlotInfo info;
  const Image image = plot_uv_layout(q.mesh, q.uv_triangles, q.uv, options, &info);
  ASSERT_EQ(image.width, 300);
  ASSERT_EQ(image.height, 200);
  EXPECT_NEAR(info.colour_range, std::log(2.0), 1e-15);  // |ln(1/2)| > ln(3/2)
  EXPECT_EQ(info.flipped_faces, 0);
  EXPECT_EQ(info.seam_halfedges, 6);  // every edge is on the boundary of a chart
  // Sample well inside each triangle: its centroid in texture space, mapped like the plot does
  // (the texture bounding box [0, 3] x [0, 1] centred in the picture above the colour bar).
  const double bar = std::max(48.0, 0.09 * 200), margin = 0.04 * 200;
  const double plot_w = 300 - 2 * margin, plot_h = 200 - bar - 2 * margin;
  const double scale = std::min(plot_w / 3.0, plot_h / 1.0);
  const double ox = margin + 0.5 * (plot_w - 3 * scale), oy = margin + 0.5 * (plot_h - scale);
  auto sample = [&](double u, double v) {
    return unpack_rgb(
        image.at(static_cast<int>(ox + u * scale), static_cast<int>(oy + (1 - v) * scale)));
  };
  const Rgb expanded = sample(2.0, 1.0 / 3);    // first triangle: ln(3/2), reddish
  const Rgb shrunk = sample(1.0 / 3, 2.0 / 3);  // second one: ln(1/2) = -range, full blue
  EXPECT_GT(expanded.r, expanded.b + 0.2);
  EXPECT_GT(shrunk.b, shrunk.r + 0.5);
  EXPECT_EQ(image.at(1, 1), pack_rgb({1, 1, 1}));
}

TEST(UvPlot, SvgHasOnePathPerFace) {
  const auto g = testing::grid_with_uv(4);  // 32 faces, the boundary a seam, no cones
  UvPlotOptions options;
  options.colour_bar = false;  // its text would add one path per glyph
  const std::string svg = plot_uv_layout_svg(g.mesh, g.uv_triangles, g.uv, options);
  EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_LT(svg.find("<svg"), svg.find("</svg>"));
  // Cairo writes each fill-and-stroke as one element: 32 faces + 1 for the seams.
  EXPECT_EQ(testing::count_occurrences(svg, "<path"), 32 + 1);
  EXPECT_EQ(testing::count_occurrences(svg, "<path"),
            testing::count_occurrences(svg, "/>") - testing::count_occurrences(svg, "<rect"));

  const auto path = testing::render_tmp_dir() / "grid_uv.svg";
  write_svg(path.string(), svg);
  EXPECT_EQ(testing::read_text_file(path), svg);
}

TEST(UvPlot, SvgMarksCones) {
  // The unrolled pyramid of uv_chart_test: one cone with two texture copies... and one path for
  // all the dots: 4 faces + seams + cones.
  const auto pyramid = testing::unrolled_pyramid(std::numbers::pi / 3);
  UvPlotOptions options;
  options.colour_bar = false;
  UvPlotInfo info;
  const std::string svg =
      plot_uv_layout_svg(pyramid.mesh, pyramid.uv_triangles, pyramid.uv, options, &info);
  EXPECT_EQ(info.cones, 1);
  EXPECT_EQ(testing::count_occurrences(svg, "<path"), 4 + 1 + 1);
}

TEST(UvPlot, RejectsBadInput) {
  const auto g = testing::grid_with_uv(2);
  UvPlotOptions options;
  options.width = 8;
  EXPECT_THROW(plot_uv_layout(g.mesh, g.uv_triangles, g.uv, options), InvalidInput);
  UV collapsed = UV::Zero(g.uv.rows(), 2);
  EXPECT_THROW(plot_uv_layout(g.mesh, g.uv_triangles, collapsed), InvalidInput);
  UV nan_uv = g.uv;
  nan_uv(2, 0) = std::nan("");
  EXPECT_THROW(plot_uv_layout_svg(g.mesh, g.uv_triangles, nan_uv), InvalidInput);
}

}  // namespace
}  // namespace ricci
