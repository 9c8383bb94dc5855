#include "ricci/param/atlas/chart_packing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "ricci/errors.hpp"
#include "ricci/numerics/predicates.hpp"

namespace ricci {
namespace {

using Points = Eigen::Matrix<double, Eigen::Dynamic, 2>;
using Triangle = std::array<Eigen::Vector2d, 3>;

/// A layout of several charts built piece by piece.
struct PieceLayout {
  std::vector<Eigen::Vector2d> points;
  std::vector<std::array<int, 3>> triangles;
  std::vector<int> face_chart;

  /// A w x h rectangle (two triangles) turned by `angle` and moved to `at`.
  void rectangle(double w, double h, double angle, const Eigen::Vector2d& at, int chart) {
    const Eigen::Rotation2Dd turn(angle);
    const int base = static_cast<int>(points.size());
    for (const Eigen::Vector2d& p : {Eigen::Vector2d(0, 0), Eigen::Vector2d(w, 0),
                                     Eigen::Vector2d(w, h), Eigen::Vector2d(0, h)}) {
      points.emplace_back(turn * p + at);
    }
    triangles.push_back({base, base + 1, base + 2});
    triangles.push_back({base, base + 2, base + 3});
    face_chart.insert(face_chart.end(), {chart, chart});
  }
  /// A regular n-gon of radius r around `at` (a fan).
  void polygon(int n, double r, const Eigen::Vector2d& at, int chart) {
    const int centre = static_cast<int>(points.size());
    points.push_back(at);
    for (int i = 0; i < n; ++i) {
      points.emplace_back(at + r * Eigen::Vector2d(std::cos(2 * std::numbers::pi * i / n),
                                                   std::sin(2 * std::numbers::pi * i / n)));
    }
    for (int i = 0; i < n; ++i) {
      triangles.push_back({centre, centre + 1 + i, centre + 1 + (i + 1) % n});
      face_chart.push_back(chart);
    }
  }
  Points uv() const {
    Points out(static_cast<Eigen::Index>(points.size()), 2);
    for (std::size_t i = 0; i < points.size(); ++i) {
      out.row(static_cast<Eigen::Index>(i)) = points[i].transpose();
    }
    return out;
  }
  Triangles faces() const {
    Triangles out(static_cast<Eigen::Index>(triangles.size()), 3);
    for (std::size_t f = 0; f < triangles.size(); ++f) {
      for (int k = 0; k < 3; ++k) out(static_cast<Eigen::Index>(f), k) = triangles[f][k];
    }
    return out;
  }
};

/// Distance from p to the segment [a, b].
double point_segment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d d = b - a;
  const double t = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (a + t * d - p).norm();
}

/// Distance between two triangles that do not overlap: the nearest points lie on an edge of one
/// and a vertex of the other.
double triangle_distance(const Triangle& a, const Triangle& b) {
  double out = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) {
      out = std::min(out, point_segment(a[i], b[k], b[(k + 1) % 3]));
      out = std::min(out, point_segment(b[i], a[k], a[(k + 1) % 3]));
    }
  }
  return out;
}

/// The properties every packing must have: uv in the square, each chart a rotation of its input
/// scaled by the common factor and moved, the faces of different charts at least a gutter apart
/// (so never overlapping; checked here by brute force), the coverage what it says.
void expect_valid_packing(const PieceLayout& input, const ChartPacking& p, double gutter) {
  const Points layout = input.uv();
  const Triangles faces = input.faces();
  ASSERT_EQ(p.uv.rows(), layout.rows());
  // Coordinates are O(1): a few ulps of rounding in the placement.
  constexpr double kRounding = 1e-12;
  EXPECT_GE(p.uv.minCoeff(), gutter / 2 - kRounding);
  EXPECT_LE(p.uv.maxCoeff(), 1 - gutter / 2 + kRounding);
  double area = 0;
  for (std::size_t c = 0; c < p.charts.size(); ++c) {
    const PackedChart& chart = p.charts[c];
    const Eigen::Rotation2Dd turn(chart.rotation);
    for (int f : chart.faces) {
      for (int k = 0; k < 3; ++k) {
        const int v = faces(f, k);
        const Eigen::Vector2d expected =
            p.scale * (turn * layout.row(v).transpose()) + chart.translation;
        EXPECT_LE((p.uv.row(v).transpose() - expected).norm(), kRounding) << "chart " << c;
      }
      const Eigen::Vector2d a = p.uv.row(faces(f, 0)).transpose();
      const Eigen::Vector2d b = p.uv.row(faces(f, 1)).transpose() - a;
      const Eigen::Vector2d d = p.uv.row(faces(f, 2)).transpose() - a;
      area += 0.5 * std::abs(b.x() * d.y() - b.y() * d.x());
    }
  }
  EXPECT_NEAR(p.coverage, area, 1e-12);
  EXPECT_EQ(p.overlapping_face_pairs, 0);
  int overlaps = 0;
  double nearest = std::numeric_limits<double>::infinity();
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    for (Eigen::Index g = f + 1; g < faces.rows(); ++g) {
      if (p.face_chart[f] == p.face_chart[g]) continue;
      Triangle a, b;
      for (int k = 0; k < 3; ++k) {
        a[k] = p.uv.row(faces(f, k)).transpose();
        b[k] = p.uv.row(faces(g, k)).transpose();
      }
      overlaps += triangles_overlap(a, b);
      nearest = std::min(nearest, triangle_distance(a, b));
    }
  }
  EXPECT_EQ(overlaps, 0);
  EXPECT_GE(nearest, gutter - kRounding);
}

TEST(FindUvOverlaps, AgreesWithEveryPairTested) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> where(0, 10), size(0.05, 1.5);
  Points uv(3 * 300, 2);
  Triangles faces(300, 3);
  std::vector<int> group(300);
  for (int f = 0; f < 300; ++f) {
    const Eigen::Vector2d at(where(rng), where(rng));
    for (int k = 0; k < 3; ++k) {
      uv.row(3 * f + k) = (at + Eigen::Vector2d(size(rng), size(rng))).transpose();
      faces(f, k) = 3 * f + k;
    }
    group[f] = f % 3;
  }
  for (const bool grouped : {false, true}) {
    int expected = 0;
    for (int f = 0; f < 300; ++f) {
      for (int g = f + 1; g < 300; ++g) {
        if (grouped && group[f] == group[g]) continue;
        Triangle a, b;
        for (int k = 0; k < 3; ++k) {
          a[k] = uv.row(3 * f + k).transpose();
          b[k] = uv.row(3 * g + k).transpose();
        }
        expected += triangles_overlap(a, b);
      }
    }
    const UvOverlaps found = find_uv_overlaps(uv, faces, grouped ? group : std::vector<int>{}, 5);
    EXPECT_GT(expected, 10);  // random triangles in a 10 x 10 box overlap often
    EXPECT_EQ(found.count, expected) << (grouped ? "grouped" : "all pairs");
    EXPECT_EQ(found.pairs.size(), 5u);
  }
}

TEST(PackCharts, EqualSquaresFillTheSquare) {
  // 16 unit squares pack 4 x 4: the scale is 1/4 less the gutter, coverage (1 - 4 g)^2 up to the
  // search's relative tolerance of 1e-3 on the scale (2e-3 on the area).
  PieceLayout input;
  for (int i = 0; i < 16; ++i) input.rectangle(1, 1, 0, Eigen::Vector2d(3.0 * i, 0), i);
  ChartPackingOptions options;
  options.gutter = 0.01;
  const ChartPacking p = pack_charts(input.uv(), input.faces(), input.face_chart, options);
  expect_valid_packing(input, p, options.gutter);
  EXPECT_NEAR(p.scale, (1 - 4 * options.gutter) / 4, 1e-3 * p.scale);
  EXPECT_NEAR(p.coverage, std::pow(1 - 4 * options.gutter, 2), 3e-3);
  EXPECT_NEAR(p.rectangle_coverage, p.coverage, 1e-12);
}

TEST(PackCharts, ChartsTurnToTheirSmallestRectangle) {
  // A 1 x 0.1 strip given at 30 degrees: turned back, it spans the square (coverage 0.1 less the
  // gutter's share); kept at 30 degrees, it covers less (below).
  PieceLayout input;
  input.rectangle(1, 0.1, std::numbers::pi / 6, Eigen::Vector2d(0.3, -2), 0);
  const ChartPacking turned = pack_charts(input.uv(), input.faces());
  expect_valid_packing(input, turned, 0.002);
  EXPECT_NEAR(
      std::remainder(turned.charts[0].rotation + std::numbers::pi / 6, std::numbers::pi / 2), 0,
      1e-12);
  EXPECT_NEAR(turned.coverage, 0.1 * std::pow(1 - 0.002, 2), 3e-4);
  ChartPackingOptions keep;
  keep.rotate = false;
  const ChartPacking kept = pack_charts(input.uv(), input.faces(), {}, keep);
  expect_valid_packing(input, kept, 0.002);
  EXPECT_EQ(kept.charts[0].rotation, 0.0);
  // At 30 degrees the strip's box is cos 30 + 0.1 sin 30 = 0.916 wide (and 0.587 high): the
  // scale is (1 - gutter) / 0.916 and the coverage 0.1 times its square, 0.119.
  const double wide = std::cos(std::numbers::pi / 6) + 0.1 * std::sin(std::numbers::pi / 6);
  EXPECT_NEAR(kept.coverage, 0.1 * std::pow((1 - 0.002) / wide, 2), 3e-4);
}

TEST(PackCharts, ManyChartsOfVeryDifferentSizesKeepTheirRelativeScale) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(0, 1);
  PieceLayout input;
  for (int c = 0; c < 120; ++c) {
    const double size = std::pow(10.0, -2 + 3 * unit(rng));  // 0.01 to 10
    const Eigen::Vector2d at(100 * unit(rng), 100 * unit(rng));
    if (c % 2 == 0) {
      input.rectangle(size, size * (0.2 + unit(rng)), 2 * std::numbers::pi * unit(rng), at, c);
    } else {
      input.polygon(3 + c % 7, size, at, c);
    }
  }
  for (const double gutter : {0.0, 0.004}) {
    ChartPackingOptions options;
    options.gutter = gutter;
    const ChartPacking p = pack_charts(input.uv(), input.faces(), input.face_chart, options);
    expect_valid_packing(input, p, std::max(gutter, 1e-9));
    // Charts are convex here, so they fill their minimal rectangles well; the rectangles pack
    // with the gutter's loss (measured 0.74 and 0.70 coverage).
    EXPECT_GT(p.coverage, gutter > 0 ? 0.6 : 0.65);
  }
}

// Past 2000 charts (a repaired tetrahedral mesh: 38802 components) the rectangles go on shelves,
// linear after a sort, where MaxRects took 59 s: the same guarantees, a packing still dense.
TEST(PackCharts, ThousandsOfChartsGoOnShelves) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(0, 1);
  PieceLayout input;
  for (int c = 0; c < 2100; ++c) {
    const double size = 0.5 + unit(rng);
    input.rectangle(size, size * (0.3 + unit(rng)), 2 * std::numbers::pi * unit(rng),
                    Eigen::Vector2d(100 * unit(rng), 100 * unit(rng)), c);
  }
  ChartPackingOptions options;
  options.gutter = 0.0005;
  options.raster_resolution = 0;  // the rectangles alone
  const ChartPacking p = pack_charts(input.uv(), input.faces(), input.face_chart, options);
  expect_valid_packing(input, p, options.gutter);
  // Measured 0.67.
  EXPECT_GT(p.coverage, 0.6);
  // One attempt per scale tried: no orders tried in turn.
  EXPECT_LT(p.packing_attempts, 40);
}

TEST(PackCharts, ShapesNestWhereRectanglesCannot) {
  // Right triangles: each fills half its rectangle, so rectangles cover at most half the square;
  // by shape, pairs of triangles turned half a turn against each other fill a rectangle.
  PieceLayout input;
  for (int c = 0; c < 40; ++c) {
    const int base = static_cast<int>(input.points.size());
    for (const Eigen::Vector2d& p :
         {Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0), Eigen::Vector2d(0, 1)}) {
      input.points.emplace_back(p + Eigen::Vector2d(2.0 * c, 0));
    }
    input.triangles.push_back({base, base + 1, base + 2});
    input.face_chart.push_back(c);
  }
  ChartPackingOptions rectangles;
  rectangles.raster_resolution = 0;
  const ChartPacking boxed = pack_charts(input.uv(), input.faces(), input.face_chart, rectangles);
  expect_valid_packing(input, boxed, rectangles.gutter);
  EXPECT_FALSE(boxed.by_shape);
  EXPECT_LT(boxed.coverage, 0.45);
  const ChartPacking shaped = pack_charts(input.uv(), input.faces(), input.face_chart);
  expect_valid_packing(input, shaped, ChartPackingOptions{}.gutter);
  EXPECT_TRUE(shaped.by_shape);
  // Measured 0.77 (rectangles 0.40): the cells along each hypotenuse and the gutter's cells cost
  // the rest.
  EXPECT_GT(shaped.coverage, 0.7);
}

TEST(PackCharts, ConnectedPiecesAreChartsByDefault) {
  PieceLayout input;
  input.rectangle(1, 2, 0, Eigen::Vector2d(0, 0), 0);
  input.polygon(5, 1, Eigen::Vector2d(0.5, 1), 1);  // overlapping the rectangle in the input
  const ChartPacking p = pack_charts(input.uv(), input.faces());
  ASSERT_EQ(p.charts.size(), 2u);
  EXPECT_EQ(p.face_chart, input.face_chart);
  expect_valid_packing(input, p, 0.002);
}

TEST(PackCharts, RefusesBadInput) {
  PieceLayout input;
  input.rectangle(1, 1, 0, Eigen::Vector2d(0, 0), 0);
  Triangles bad = input.faces();
  bad(1, 2) = 7;
  EXPECT_THROW(pack_charts(input.uv(), bad), InvalidInput);
  ChartPackingOptions negative;
  negative.gutter = -0.1;
  EXPECT_THROW(pack_charts(input.uv(), input.faces(), {}, negative), InvalidInput);
  EXPECT_THROW(pack_charts(input.uv(), input.faces(), {0}), InvalidInput);     // wrong size
  EXPECT_THROW(pack_charts(input.uv(), input.faces(), {0, 2}), InvalidInput);  // chart 1 empty
  // Two charts sharing a position could not both be placed.
  EXPECT_THROW(pack_charts(input.uv(), input.faces(), {0, 1}), InvalidInput);
  Points nan = input.uv();
  nan(2, 0) = std::nan("");
  EXPECT_THROW(pack_charts(nan, input.faces()), InvalidInput);
}

}  // namespace
}  // namespace ricci
