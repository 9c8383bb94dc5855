// The software renderer: checker pattern on a flat grid, the z-buffer, seams and cones, the
// automatic view and the checks on its options.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "render_test_support.hpp"
#include "ricci/errors.hpp"
#include "ricci/render/render_mesh.hpp"

namespace ricci {
namespace {

using UV = Eigen::Matrix<double, Eigen::Dynamic, 2>;

/// The colour of the pixel under a world point.
Rgb pixel_at(const RenderResult& r, const Eigen::Vector3d& point) {
  const Eigen::Vector2d p = r.camera.project(point);
  return unpack_rgb(
      r.image.at(static_cast<int>(std::floor(p.x())), static_cast<int>(std::floor(p.y()))));
}

/// The default checker colours are a near-grey and a blue: tell them apart under any shading.
bool is_light_square(const Rgb& c) {
  return std::abs(c.b - c.r) < 0.05 && c.r > 0.3;
}
bool is_dark_square(const Rgb& c) {
  return c.b - c.r > 0.15;
}

TEST(RenderMesh, CheckerOfAFlatGridSeenFromAbove) {
  const auto g = testing::grid_with_uv(8);
  RenderOptions options;
  options.width = 400;
  options.height = 300;
  options.checker = 4;
  const RenderResult r = render_textured_mesh(g.mesh, g.uv_triangles, g.uv, options);
  ASSERT_EQ(r.image.width, 400);
  ASSERT_EQ(r.image.height, 300);
  // The automatic view of a flat mesh looks straight down its normal, +y up.
  EXPECT_NEAR(r.camera.view.z(), 1.0, 1e-15);
  EXPECT_NEAR(r.camera.up.y(), 1.0, 1e-15);
  EXPECT_EQ(r.visible_faces, g.mesh.num_faces());
  // The unit square fills the picture's height but for the 5% margin (15 px), centred.
  EXPECT_NEAR(r.camera.project({0, 0, 0}).x(), 200 - 135, 1e-9);
  EXPECT_NEAR(r.camera.project({0, 0, 0}).y(), 300 - 15, 1e-9);
  EXPECT_NEAR(r.camera.project({1, 1, 0}).y(), 15, 1e-9);

  // Square (i, j) covers [i/4, (i+1)/4) x [j/4, (j+1)/4) of the texture: light when i + j is
  // even. A flat grid is lit evenly, so all squares of one parity have one colour.
  const std::uint32_t light = r.image.at(static_cast<int>(r.camera.project({0.125, 0.125, 0}).x()),
                                         static_cast<int>(r.camera.project({0.125, 0.125, 0}).y()));
  const std::uint32_t dark = r.image.at(static_cast<int>(r.camera.project({0.375, 0.125, 0}).x()),
                                        static_cast<int>(r.camera.project({0.375, 0.125, 0}).y()));
  EXPECT_TRUE(is_light_square(unpack_rgb(light)));
  EXPECT_TRUE(is_dark_square(unpack_rgb(dark)));
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      const Eigen::Vector2d p = r.camera.project({(i + 0.5) / 4, (j + 0.5) / 4, 0});
      EXPECT_EQ(r.image.at(static_cast<int>(p.x()), static_cast<int>(p.y())),
                (i + j) % 2 == 0 ? light : dark)
          << "square " << i << ", " << j;
    }
  }
  // Background around the grid; the boundary (a seam of the chart) drawn dark.
  const std::uint32_t background = pack_rgb(options.background);
  EXPECT_EQ(r.image.at(0, 0), background);
  EXPECT_EQ(r.image.at(399, 299), background);
  EXPECT_EQ(r.image.at(30, 150), background);   // left of the grid (which starts at x = 65)
  EXPECT_EQ(r.image.at(370, 150), background);  // right of it (ends at x = 335)
  const Rgb edge = pixel_at(r, {0.0, 0.5, 0});
  EXPECT_LT(edge.r + edge.g + edge.b, 1.5);
  EXPECT_EQ(r.seam_edges, 32);
  EXPECT_EQ(r.cones, 0);
}

TEST(RenderMesh, HomogeneousWeightsInterpolateProjectively) {
  // One triangle (0,0,0), (1,0,0), (0,1,0) with uv equal to its x and y; weights (1, 4, 1).
  // At the point of barycentric coordinates b the texture coordinates are
  // sum b_i w_i uv_i / sum b_i w_i: at (0.3, 0.1), b = (0.6, 0.3, 0.1), u = 1.2 / 1.9 = 0.63,
  // in the second checker column of two, where linear interpolation (u = 0.3) is in the first.
  Mesh mesh;
  mesh.positions.resize(3, 3);
  mesh.positions << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  mesh.triangles.resize(1, 3);
  mesh.triangles << 0, 1, 2;
  UV uv(3, 2);
  uv << 0, 0, 1, 0, 0, 1;
  RenderOptions options;
  options.width = options.height = 200;
  options.checker = 2;
  options.draw_seams = false;
  const RenderResult linear = render_textured_mesh(mesh, mesh.triangles, uv, options);
  EXPECT_TRUE(is_light_square(pixel_at(linear, {0.3, 0.1, 0})));
  EXPECT_TRUE(is_dark_square(pixel_at(linear, {0.6, 0.1, 0})));
  options.uv_weights = Eigen::VectorXd{{1, 4, 1}};
  const RenderResult projective = render_textured_mesh(mesh, mesh.triangles, uv, options);
  EXPECT_TRUE(is_dark_square(pixel_at(projective, {0.3, 0.1, 0})));
  // At (0.04, 0.1): b = (0.86, 0.04, 0.1), u = 0.16 / 1.12 = 0.14, v = 0.09: the first square.
  EXPECT_TRUE(is_light_square(pixel_at(projective, {0.04, 0.1, 0})));
  options.uv_weights = Eigen::VectorXd{{1, -1, 1}};
  EXPECT_THROW(render_textured_mesh(mesh, mesh.triangles, uv, options), InvalidInput);
  options.uv_weights = Eigen::VectorXd{{1, 1}};
  EXPECT_THROW(render_textured_mesh(mesh, mesh.triangles, uv, options), InvalidInput);
}

TEST(RenderMesh, NearestSurfaceWinsTheZBuffer) {
  // Quad A at z = 0 over [0, 1] x [0, 1] with a light texture, quad B at z = 0.5 over
  // [0.5, 1.5] x [0, 1] with a dark one; they overlap over [0.5, 1] x [0, 1].
  Mesh mesh;
  mesh.positions.resize(8, 3);
  mesh.positions << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0,  //
      0.5, 0, 0.5, 1.5, 0, 0.5, 1.5, 1, 0.5, 0.5, 1, 0.5;
  UV uv(2, 2);
  uv << 0.1, 0.1, 0.3, 0.1;  // with 4 squares per unit: square (0, 0) light, (1, 0) dark
  for (bool b_first : {false, true}) {
    mesh.triangles.resize(4, 3);
    Triangles uv_triangles(4, 3);
    const Eigen::RowVector3i a0(0, 1, 2), a1(0, 2, 3), b0(4, 5, 6), b1(4, 6, 7);
    if (b_first) {
      mesh.triangles << b0, b1, a0, a1;
      uv_triangles << 1, 1, 1, 1, 1, 1, 0, 0, 0, 0, 0, 0;
    } else {
      mesh.triangles << a0, a1, b0, b1;
      uv_triangles << 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1;
    }
    RenderOptions options;
    options.width = options.height = 200;
    options.checker = 4;
    options.draw_seams = false;
    options.view = {0, 0, 1};
    const RenderResult above = render_textured_mesh(mesh, uv_triangles, uv, options);
    EXPECT_TRUE(is_light_square(pixel_at(above, {0.25, 0.5, 0})));
    EXPECT_TRUE(is_dark_square(pixel_at(above, {0.75, 0.5, 0.5})));  // B in front of A
    EXPECT_TRUE(is_dark_square(pixel_at(above, {1.25, 0.5, 0.5})));
    options.view = {0, 0, -1};
    const RenderResult below = render_textured_mesh(mesh, uv_triangles, uv, options);
    EXPECT_TRUE(is_light_square(pixel_at(below, {0.25, 0.5, 0})));
    EXPECT_TRUE(is_light_square(pixel_at(below, {0.75, 0.5, 0})));  // now A in front of B
    EXPECT_TRUE(is_dark_square(pixel_at(below, {1.25, 0.5, 0.5})));
  }
}

TEST(RenderMesh, MarksTheConeOfAnUnrolledPyramid) {
  // Pyramid with apex (0, 0, 1) over the square of corners (+-1, 0), (0, +-1); its texture
  // unrolls the four faces with 60 degree corners at the apex: a cone, on the seam apex-1.
  const auto pyramid = testing::unrolled_pyramid(std::numbers::pi / 3);
  RenderOptions options;
  options.width = options.height = 240;
  options.view = {0, 0, 1};
  const RenderResult r =
      render_textured_mesh(pyramid.mesh, pyramid.uv_triangles, pyramid.uv, options);
  EXPECT_EQ(r.cones, 1);
  EXPECT_EQ(r.visible_cones, 1);
  EXPECT_EQ(r.seam_edges, 5);
  const Rgb apex = pixel_at(r, {0, 0, 1});
  EXPECT_GT(apex.r, 0.7);
  EXPECT_LT(apex.g, 0.3);
  // From below, the apex shows through the open base.
  options.view = {0, 0, -1};
  EXPECT_EQ(
      render_textured_mesh(pyramid.mesh, pyramid.uv_triangles, pyramid.uv, options).visible_cones,
      1);
}

TEST(RenderMesh, HiddenSeamsAndConesAreNotDrawn) {
  // A closed surface: the tetrahedron with every face its own chart, seen from one face's side.
  const Mesh tet = make_tetrahedron(1.0);
  Triangles uv_triangles(4, 3);
  UV uv(12, 2);
  for (int f = 0; f < 4; ++f) {
    uv_triangles.row(f) << 3 * f, 3 * f + 1, 3 * f + 2;
    uv.row(3 * f) << 0, 0;
    uv.row(3 * f + 1) << 1, 0;
    uv.row(3 * f + 2) << 0.5, 0.8;
  }
  // Every vertex has three texture corners adding up to about pi: all four are cones.
  RenderOptions options;
  options.width = options.height = 120;
  const Eigen::Vector3d centroid = tet.positions.colwise().mean();
  const Eigen::Vector3d apex = tet.positions.row(0).transpose() - centroid;
  options.view = apex;  // vertex 0 in front, in the middle of the picture
  const RenderResult front = render_textured_mesh(tet, uv_triangles, uv, options);
  EXPECT_EQ(front.seam_edges, 6);
  EXPECT_EQ(front.cones, 4);
  EXPECT_EQ(front.visible_cones, 4);
  options.view = -apex;  // vertex 0 straight behind the face opposite to it
  const RenderResult back = render_textured_mesh(tet, uv_triangles, uv, options);
  EXPECT_EQ(back.visible_cones, 3);
  // The picture's centre shows that face, not the hidden cone's red.
  const Rgb centre = unpack_rgb(back.image.at(60, 60));
  EXPECT_LT(centre.r - centre.b, 0.1);
}

TEST(RenderMesh, AutomaticViews) {
  Eigen::Vector3d up;
  // Flat: straight along the least-extent axis.
  const Eigen::Vector3d flat = automatic_view(make_grid(3, 2, 2.0, 1.0), &up);
  EXPECT_NEAR(flat.z(), 1.0, 1e-15);
  EXPECT_NEAR(up.y(), 1.0, 1e-15);
  // Flattish (the torus, 2.8 x 2.8 x 0.8): 40 degrees above its plane, z up on screen.
  const Eigen::Vector3d torus = automatic_view(make_torus(24, 12), &up);
  EXPECT_NEAR(torus.z(), std::sin(40 * std::numbers::pi / 180), 1e-12);
  EXPECT_NEAR(torus.norm(), 1.0, 1e-15);
  EXPECT_NEAR(torus.dot(up), 0.0, 1e-15);
  EXPECT_GT(up.z(), 0.5);
  // Round: a 3/4 view with +y up.
  const Eigen::Vector3d sphere = automatic_view(make_icosphere(1), &up);
  EXPECT_GT(sphere.x(), 0.3);
  EXPECT_GT(sphere.y(), 0.2);
  EXPECT_GT(sphere.z(), 0.7);
  EXPECT_NEAR(sphere.dot(up), 0.0, 1e-15);
}

TEST(RenderMesh, RejectsBadInput) {
  const auto g = testing::grid_with_uv(2);
  RenderOptions options;
  options.width = options.height = 32;
  RenderOptions bad = options;
  bad.checker = 0;
  EXPECT_THROW(render_textured_mesh(g.mesh, g.uv_triangles, g.uv, bad), InvalidInput);
  bad = options;
  bad.supersampling = 0;
  EXPECT_THROW(render_textured_mesh(g.mesh, g.uv_triangles, g.uv, bad), InvalidInput);
  bad = options;
  bad.width = 0;
  EXPECT_THROW(render_textured_mesh(g.mesh, g.uv_triangles, g.uv, bad), InvalidInput);
  bad = options;
  bad.view = {0, 1, 0};
  bad.up = {0, 2, 0};
  EXPECT_THROW(render_textured_mesh(g.mesh, g.uv_triangles, g.uv, bad), InvalidInput);
  EXPECT_THROW(render_textured_mesh(g.mesh, g.uv_triangles.topRows(2), g.uv, options),
               InvalidInput);
  Mesh nan_mesh = g.mesh;
  nan_mesh.positions(3, 1) = std::nan("");
  EXPECT_THROW(render_textured_mesh(nan_mesh, g.uv_triangles, g.uv, options), InvalidInput);
}

}  // namespace
}  // namespace ricci
