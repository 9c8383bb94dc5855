// The tiling picture: the regular octagon of a genus-2 surface, meshed, and its images under the
// side pairings (and under the canonical generators) fill the disk.

#include "ricci/render/tiling.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <numbers>
#include <set>

#include "render_test_support.hpp"
#include "ricci/errors.hpp"
#include "ricci/hyperbolic/fuchsian.hpp"
#include "support/hyperbolic_polygons.hpp"

namespace ricci {
namespace {

using Complex = std::complex<double>;
using DiskPoints = Eigen::Matrix<double, Eigen::Dynamic, 2>;

/// A polygon of the disk meshed: each side divided into `per_side` pieces along its geodesic,
/// `rings` rings of vertices scaled towards the centre (the rays from the centre are geodesics
/// inside the convex polygon), a fan at the centre.
struct DomainMesh {
  DiskPoints positions;
  Triangles triangles;
};

DomainMesh mesh_polygon(const std::vector<Complex>& corners, int per_side, int rings) {
  std::vector<Complex> boundary;
  const int n = static_cast<int>(corners.size());
  for (int k = 0; k < n; ++k) {
    const Mobius t = translation_to_origin(corners[k]);
    const Complex end = apply_mobius(t, corners[(k + 1) % n]);
    const double length = disk_distance(corners[k], corners[(k + 1) % n]);
    for (int s = 0; s < per_side; ++s) {
      // At hyperbolic distance s / per_side * length from the corner: radius tanh(d / 2).
      const double r = std::tanh(0.5 * length * s / per_side);
      boundary.push_back(apply_mobius(inverse(t), r * end / std::abs(end)));
    }
  }
  const int m = static_cast<int>(boundary.size());
  DomainMesh mesh;
  mesh.positions.resize(1 + rings * m, 2);
  mesh.positions.row(0) << 0, 0;
  for (int ring = 1; ring <= rings; ++ring) {
    for (int q = 0; q < m; ++q) {
      const Complex z = boundary[q] * (static_cast<double>(ring) / rings);
      mesh.positions.row(1 + (ring - 1) * m + q) << z.real(), z.imag();
    }
  }
  auto vertex = [&](int ring, int q) { return ring == 0 ? 0 : 1 + (ring - 1) * m + (q % m); };
  // (No reserve: g++ cannot bound m (2 rings - 1) and warns of an allocation beyond the maximum.)
  std::vector<Eigen::Vector3i> faces;
  // NOLINTNEXTLINE(performance-inefficient-vector-operation)
  for (int q = 0; q < m; ++q) faces.emplace_back(0, vertex(1, q), vertex(1, q + 1));
  for (int ring = 1; ring < rings; ++ring) {
    for (int q = 0; q < m; ++q) {
      faces.emplace_back(vertex(ring, q), vertex(ring + 1, q), vertex(ring + 1, q + 1));
      faces.emplace_back(vertex(ring, q), vertex(ring + 1, q + 1), vertex(ring, q + 1));
    }
  }
  mesh.triangles.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    mesh.triangles.row(static_cast<Eigen::Index>(f)) = faces[f].transpose();
  }
  return mesh;
}

struct Octagon {
  DomainMesh mesh;
  std::vector<Mobius> side_pairings;
};

Octagon octagon() {
  const auto polygon = testing::regular_surface_polygon(2, testing::canonical_sides(2));
  return {mesh_polygon(polygon.corners, 8, 6), testing::side_pairings(polygon)};
}

/// A `size`-pixel picture of the images under words of at most `max_word_length` generators.
TilingOptions tiling_options(int size, int max_word_length) {
  TilingOptions options;
  options.size = size;
  options.max_word_length = max_word_length;
  return options;
}

TEST(Tiling, PngOfTheOctagonTilesTheDisk) {
  const Octagon o = octagon();
  const TilingOptions options = tiling_options(512, 6);
  TilingInfo info;
  const Image image =
      draw_tiling(o.mesh.positions, o.mesh.triangles, o.side_pairings, options, &info);
  ASSERT_EQ(image.width, 512);
  ASSERT_EQ(image.height, 512);
  EXPECT_EQ(info.boundary_loops, 1);
  EXPECT_GT(info.images_drawn, 100);
  EXPECT_GT(info.duplicates, 0);  // the vertex relation closes cycles of words
  std::printf(
      "[ measured ] octagon, 512 px, words <= 6: %d images drawn, %d too small, %d "
      "duplicate words\n",
      info.images_drawn, info.images_too_small, info.duplicates);

  std::set<std::uint32_t> colours(image.pixels.begin(), image.pixels.end());
  EXPECT_GT(colours.size(), 8u);
  // Centre: the domain's colour; a corner of the picture: the background.
  const double c = 256;
  // (up to the faint mesh edges blended in).
  const Rgb centre = unpack_rgb(image.at(static_cast<int>(c) + 40, static_cast<int>(c) + 17));
  EXPECT_NEAR(centre.r, options.domain_colour.r, 0.1);
  EXPECT_NEAR(centre.g, options.domain_colour.g, 0.1);
  EXPECT_NEAR(centre.b, options.domain_colour.b, 0.1);
  EXPECT_EQ(image.at(2, 2), pack_rgb(options.background));
  // The images cover the disk: few pixels inside radius 0.8 keep the empty disk's colour.
  const double radius = 0.5 * 512 - std::max(2.0, 0.02 * 512);
  int inside = 0, empty = 0;
  for (int y = 0; y < 512; ++y) {
    for (int x = 0; x < 512; ++x) {
      if (std::hypot(x + 0.5 - c, y + 0.5 - c) > 0.8 * radius) continue;
      ++inside;
      empty += image.at(x, y) == pack_rgb(options.disk_colour);
    }
  }
  EXPECT_LT(empty, inside / 1000) << empty << " of " << inside;
  write_png((testing::render_tmp_dir() / "tiling_octagon.png").string(), image);
}

TEST(Tiling, SvgHasOnePathPerImage) {
  const Octagon o = octagon();
  const TilingOptions options = tiling_options(400, 3);
  TilingInfo info;
  const std::string svg =
      draw_tiling_svg(o.mesh.positions, o.mesh.triangles, o.side_pairings, options, &info);
  EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
  EXPECT_LT(svg.find("<svg"), svg.find("</svg>"));
  // Words of length <= 3 in 4 generators and inverses: 8 + 8 * 7 + 8 * 7 * 7 reduced words,
  // fewer after the duplicates the vertex relation makes and the small images.
  EXPECT_GT(info.images_drawn, 40);
  EXPECT_LE(info.images_drawn, 8 + 56 + 392);
  // Disk, images, domain fill with outline, mesh edges, circle.
  EXPECT_EQ(testing::count_occurrences(svg, "<path"), 1 + info.images_drawn + 1 + 1 + 1);
  const auto path = testing::render_tmp_dir() / "tiling_octagon.svg";
  write_svg(path.string(), svg);
  EXPECT_EQ(testing::read_text_file(path), svg);
}

TEST(Tiling, CanonicalGeneratorsFindTheSameTiles) {
  // The Fuchsian group's canonical generators generate the same group: with long enough words
  // they reach the same tiles near the centre.
  const auto polygon = testing::regular_surface_polygon(2, testing::opposite_sides(4));
  const SegmentRelations relations = testing::polygon_relations(polygon);
  const FuchsianGroup group = fuchsian_group(relations);
  std::vector<Mobius> canonical = group.a;
  canonical.insert(canonical.end(), group.b.begin(), group.b.end());
  const DomainMesh mesh = mesh_polygon(polygon.corners, 4, 3);
  TilingOptions options = tiling_options(256, 8);
  options.min_image_pixels = 12;
  TilingInfo by_sides, by_canonical;
  draw_tiling(mesh.positions, mesh.triangles, relations.segment_maps, options, &by_sides);
  draw_tiling(mesh.positions, mesh.triangles, canonical, options, &by_canonical);
  EXPECT_GT(by_sides.images_drawn, 20);
  EXPECT_NEAR(by_canonical.images_drawn, by_sides.images_drawn, 0.2 * by_sides.images_drawn);
}

TEST(Tiling, RejectsBadInput) {
  const Octagon o = octagon();
  TilingOptions options;
  options.size = 8;
  EXPECT_THROW(draw_tiling(o.mesh.positions, o.mesh.triangles, o.side_pairings, options),
               InvalidInput);
  DiskPoints outside = o.mesh.positions;
  outside(3, 0) = 1.5;
  EXPECT_THROW(draw_tiling(outside, o.mesh.triangles, o.side_pairings), InvalidInput);
  Triangles bad = o.mesh.triangles;
  bad(0, 1) = 100000;
  EXPECT_THROW(draw_tiling_svg(o.mesh.positions, bad, o.side_pairings), InvalidInput);
  EXPECT_THROW(draw_tiling(o.mesh.positions, o.mesh.triangles, {Mobius{0.1, 1.0}}), InvalidInput);
}

}  // namespace
}  // namespace ricci
