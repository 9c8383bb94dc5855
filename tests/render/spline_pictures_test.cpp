// The pictures of `ricci spline --pictures`: the four files, one camera for the three renders,
// the surface's texture carrying the domain's seams and cones; and the renderer's options they
// use (a given camera, fit_camera with extra points, the wireframe).

#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include "render_test_support.hpp"
#include "ricci/errors.hpp"
#include "ricci/render/spline_pictures.hpp"
#include "ricci/render/uv_chart.hpp"

namespace ricci {
namespace {

namespace fs = std::filesystem;

/// Pixels that are not the white background, and the number of distinct colours.
struct PixelStats {
  int foreground = 0;
  int colours = 0;
};
PixelStats pixel_stats(const Image& image) {
  PixelStats s;
  std::set<std::uint32_t> colours;
  for (std::uint32_t p : image.pixels) {
    colours.insert(p);
    if (p != pack_rgb({1, 1, 1})) ++s.foreground;
  }
  s.colours = static_cast<int>(colours.size());
  return s;
}

SplineResult torus_spline() {
  SplineOptions options;  // genus 1: no cones
  options.refine = 2;
  return fit_manifold_spline(make_torus(24, 12), options);
}

TEST(SplinePictures, WritesFourPicturesFromOneCamera) {
  const SplineResult spline = torus_spline();
  ASSERT_TRUE(spline.converged) << spline.message;
  const fs::path folder = testing::render_tmp_dir() / "spline_pictures" / "nested";
  fs::remove_all(folder.parent_path());
  SplinePicturesOptions options;
  options.render.width = 200;
  options.render.height = 160;
  options.uv.width = options.uv.height = 180;
  const SplinePicturesResult written = write_spline_pictures(folder.string(), spline, options);
  ASSERT_EQ(written.files.size(), 4u);
  int entries = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(folder)) ++entries;
  EXPECT_EQ(entries, 4);  // no temporary files left behind

  const Image domain = read_png((folder / "domain.png").string());
  const Image net = read_png((folder / "control_net.png").string());
  const Image surface = read_png((folder / "surface.png").string());
  const Image layout = read_png((folder / "layout.png").string());
  for (const Image* image : {&domain, &net, &surface}) {
    EXPECT_EQ(image->width, 200);
    EXPECT_EQ(image->height, 160);
  }
  EXPECT_EQ(layout.width, 180);
  EXPECT_EQ(layout.height, 180);

  // Every picture shows something: a torus in a 3/4 view covers a good part of the picture.
  for (const Image* image : {&domain, &net, &surface, &layout}) {
    const PixelStats s = pixel_stats(*image);
    EXPECT_GT(s.foreground, image->width * image->height / 5);
    EXPECT_GT(s.colours, 50);  // shading and anti-aliasing, not a flat fill
  }
  // The three renders differ (texture, wireframe, smooth shading) ...
  EXPECT_NE(domain.pixels, net.pixels);
  EXPECT_NE(domain.pixels, surface.pixels);
  EXPECT_NE(net.pixels, surface.pixels);
  // ... and were seen through one camera: the surface stays within 1% of the bounding-box
  // diagonal of the torus, so their silhouettes nearly coincide.
  int differing = 0, covered = 0;
  for (std::size_t i = 0; i < domain.pixels.size(); ++i) {
    const bool a = domain.pixels[i] != pack_rgb({1, 1, 1});
    const bool b = surface.pixels[i] != pack_rgb({1, 1, 1});
    covered += a || b;
    differing += a != b;
  }
  EXPECT_LT(differing, covered / 20) << differing << " of " << covered;
  EXPECT_GT(written.domain_visible_faces, 0);
  EXPECT_GT(written.net_visible_faces, 0);
  EXPECT_GT(written.surface_visible_faces, 0);
  EXPECT_EQ(written.surface_cones, 0);  // a flat torus has none
  EXPECT_EQ(written.camera.width, 200);
}

// The texture of the surface repeats the domain's: every domain seam edge appears as
// 2 refine surface edges (two piece sides per mesh edge, refine segments each), and the cones
// come back at the same places.
TEST(SplinePictures, SurfaceTextureKeepsTheSeamsAndCones) {
  for (int refine : {1, 3}) {
    SplineOptions options;
    options.refine = refine;
    const SplineResult spline = fit_manifold_spline(make_closed_surface(2, 10), options);
    ASSERT_TRUE(spline.converged) << spline.message;
    ASSERT_FALSE(spline.param.cones.empty());
    const SplineSurfaceTexture texture = spline_surface_texture(spline);
    ASSERT_EQ(texture.uv_triangles.rows(), spline.surface.num_faces());
    const UvChart domain =
        analyse_uv_chart(spline.param.mesh, spline.param.cut_mesh.triangles, spline.param.uv, 1e-6);
    const UvChart surface =
        analyse_uv_chart(spline.surface, texture.uv_triangles, texture.uv, 1e-6);
    EXPECT_GT(domain.seam_edges, 0);
    EXPECT_EQ(surface.seam_edges, 2 * refine * domain.seam_edges) << "refine " << refine;
    EXPECT_EQ(surface.cones.size(), spline.param.cones.size()) << "refine " << refine;
    EXPECT_EQ(domain.cones.size(), spline.param.cones.size());
    // Texture coordinates stay in the unit square of the layout.
    EXPECT_GE(texture.uv.minCoeff(), -1e-12);
    EXPECT_LE(texture.uv.maxCoeff(), 1 + 1e-12);
  }
}

TEST(SplinePictures, RefusesASplineWithoutSurface) {
  const fs::path folder = testing::render_tmp_dir() / "spline_pictures_none";
  EXPECT_THROW(write_spline_pictures(folder.string(), SplineResult{}), InvalidInput);
  EXPECT_THROW(spline_surface_texture(SplineResult{}), InvalidInput);
}

TEST(RenderOptionsForSplines, GivenCameraAndFramedPoints) {
  const auto g = testing::grid_with_uv(4);
  RenderOptions options;
  options.width = options.height = 100;
  options.margin = 0;
  const Camera alone = fit_camera(g.mesh, options);
  Positions far(1, 3);
  far << 3, 0.5, 0;  // the grid is [0, 1]^2: the framed width triples
  const Camera both = fit_camera(g.mesh, options, far);
  EXPECT_NEAR(both.scale, alone.scale / 3, 1e-9 * alone.scale);
  // The renderer uses a given camera as it is: the grid fills only the left third.
  options.camera = both;
  const RenderResult r = render_textured_mesh(g.mesh, g.uv_triangles, g.uv, options);
  EXPECT_NEAR(r.camera.scale, both.scale, 1e-12);
  int right_half = 0;
  for (int y = 0; y < 100; ++y) {
    for (int x = 50; x < 100; ++x) right_half += r.image.at(x, y) != pack_rgb({1, 1, 1});
  }
  EXPECT_EQ(right_half, 0);
  options.camera->scale = 0;
  EXPECT_THROW(render_textured_mesh(g.mesh, g.uv_triangles, g.uv, options), InvalidInput);
}

TEST(RenderOptionsForSplines, WireframeDrawsEveryEdge) {
  const auto g = testing::grid_with_uv(3);  // 9 quads: 16 vertices, 33 edges
  RenderOptions options;
  options.width = options.height = 120;
  options.checker_light = options.checker_dark = {0.9, 0.9, 0.9};
  options.draw_seams = options.mark_cones = false;
  const RenderResult plain = render_textured_mesh(g.mesh, g.uv_triangles, g.uv, options);
  options.draw_edges = true;
  options.edge_colour = {0, 0, 1};
  options.edge_width = 1.5;
  const RenderResult wire = render_textured_mesh(g.mesh, g.uv_triangles, g.uv, options);
  EXPECT_EQ(plain.edges, 0);
  EXPECT_EQ(wire.edges, 33);
  int blue = 0;
  for (std::uint32_t p : wire.image.pixels) {
    const Rgb c = unpack_rgb(p);
    blue += c.b - c.r > 0.3;
  }
  // 33 edges of about 100 / 3 pixels each, 1.5 pixels wide: well over a thousand pixels.
  EXPECT_GT(blue, 1000);
  for (std::uint32_t p : plain.image.pixels) {
    const Rgb c = unpack_rgb(p);
    EXPECT_LT(c.b - c.r, 0.05);
  }
}

}  // namespace
}  // namespace ricci
