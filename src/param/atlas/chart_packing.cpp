#include "ricci/param/atlas/chart_packing.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <numeric>
#include <string>

#include <Eigen/Geometry>

#include "param/atlas/detail/uv_input.hpp"
#include "ricci/errors.hpp"
#include "ricci/numerics/convex_hull.hpp"
#include "ricci/numerics/disjoint_sets.hpp"
#include "ricci/numerics/predicates.hpp"
#include "ricci/numerics/timer.hpp"

namespace ricci {
namespace {

using atlas_detail::check_uv_input;
using atlas_detail::uv_point;

using Points = Eigen::Matrix<double, Eigen::Dynamic, 2>;
/// The gutter never goes below this: the placement's rounding (a few ulps of 1) stays inside it.
constexpr double kMinGutter = 1e-9;
/// Above this many charts the rectangles go on shelves instead of MaxRects: MaxRects scans every
/// free rectangle per chart (quadratic: 38802 charts of a repaired tetrahedral mesh took 59 s),
/// and with that many charts each is a small part of the square, where shelves lose little.
constexpr int kShelvesAbove = 2000;
/// The scale searches stop at this relative precision at the finest, whatever
/// ChartPackingOptions::scale_tolerance asks: with 0 a bisection would stall an ulp apart and
/// never end.
constexpr double kMinScaleTolerance = 1e-12;
/// The rectangles' search steps down from its upper bound by this factor until they fit, at most
/// kScaleStepsDown times (0.8^60 is about 1.5e-6 of the bound; below that, zero size).
constexpr double kScaleStepDown = 0.8;
constexpr int kScaleStepsDown = 60;
/// The shapes' search starts at the rectangles' scale, stepping down by this factor at most
/// kShapeStartTries times while they do not fit (their cells round outlines and gutters up).
constexpr double kShapeStartStepDown = 0.97;
constexpr int kShapeStartTries = 4;
/// From a scale where the shapes fit, the search steps up by this factor while they still fit.
constexpr double kShapeStepUp = 1.1;
/// A cell joins a chart's raster when a triangle comes within this of it (uv units): far above
/// the rounding of the placement (a few ulps of 1), so that no cell a triangle reaches is missed.
constexpr double kRasterMargin = 1e-12;

/// Twice the signed area of face f.
double twice_area(const Points& uv, const Triangles& triangles, Eigen::Index f) {
  const Eigen::Vector2d a = uv_point(uv, triangles(f, 0));
  const Eigen::Vector2d b = uv_point(uv, triangles(f, 1)) - a;
  const Eigen::Vector2d c = uv_point(uv, triangles(f, 2)) - a;
  return b.x() * c.y() - b.y() * c.x();
}

/// Charts as connected pieces of the triangles (faces sharing a vertex), numbered in order of
/// their first face.
std::vector<int> connected_pieces(const Triangles& triangles, Eigen::Index num_points) {
  DisjointSets pieces(static_cast<int>(num_points));
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    for (int k = 1; k < 3; ++k) pieces.unite(triangles(f, 0), triangles(f, k));
  }
  std::vector<int> root_chart(num_points, -1);
  std::vector<int> face_chart(triangles.rows());
  int charts = 0;
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    int& c = root_chart[pieces.find(triangles(f, 0))];
    if (c < 0) c = charts++;
    face_chart[f] = c;
  }
  return face_chart;
}

/// An axis-aligned rectangle [x0, x1] x [y0, y1]. Coordinates are only ever copied from one
/// rectangle to another or computed once as x0 + width, so rectangles that the packer keeps apart
/// are apart in floating point too.
struct Rect {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool overlaps(const Rect& o) const { return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1; }
  bool contains(const Rect& o) const {
    return x0 <= o.x0 && y0 <= o.y0 && o.x1 <= x1 && o.y1 <= y1;
  }
};

/// MaxRects (maximal free rectangles, best short side fit) in the unit square. sizes are the
/// padded widths and heights; items are placed in `order`. Returns false as soon as one item
/// does not fit.
bool pack_rectangles(const std::vector<Eigen::Vector2d>& sizes, const std::vector<int>& order,
                     bool allow_turn, std::vector<Rect>& placed, std::vector<char>& turned) {
  std::vector<Rect> free{{0, 0, 1, 1}};
  std::vector<Rect> split;
  placed.assign(sizes.size(), Rect{});
  turned.assign(sizes.size(), 0);
  for (int item : order) {
    double best_short = std::numeric_limits<double>::infinity(), best_long = best_short;
    int best_free = -1;
    bool best_turn = false;
    for (std::size_t r = 0; r < free.size(); ++r) {
      const Rect& f = free[r];
      for (int turn = 0; turn < (allow_turn ? 2 : 1); ++turn) {
        const double w = turn ? sizes[item].y() : sizes[item].x();
        const double h = turn ? sizes[item].x() : sizes[item].y();
        if (f.x0 + w > f.x1 || f.y0 + h > f.y1) continue;
        const double dw = f.x1 - f.x0 - w, dh = f.y1 - f.y0 - h;
        const double shorter = std::min(dw, dh), longer = std::max(dw, dh);
        if (shorter < best_short || (shorter == best_short && longer < best_long)) {
          best_short = shorter, best_long = longer, best_free = static_cast<int>(r);
          best_turn = turn;
        }
      }
    }
    if (best_free < 0) return false;
    const Rect& f = free[best_free];
    const double w = best_turn ? sizes[item].y() : sizes[item].x();
    const double h = best_turn ? sizes[item].x() : sizes[item].y();
    const Rect p{f.x0, f.y0, f.x0 + w, f.y0 + h};
    placed[item] = p;
    turned[item] = best_turn;
    // Split every free rectangle the new one overlaps into its (up to four) maximal remainders.
    split.clear();
    std::size_t kept = 0;
    for (std::size_t r = 0; r < free.size(); ++r) {
      const Rect g = free[r];
      if (!g.overlaps(p)) {
        free[kept++] = g;
        continue;
      }
      if (p.x0 > g.x0) split.push_back({g.x0, g.y0, p.x0, g.y1});
      if (p.x1 < g.x1) split.push_back({p.x1, g.y0, g.x1, g.y1});
      if (p.y0 > g.y0) split.push_back({g.x0, g.y0, g.x1, p.y0});
      if (p.y1 < g.y1) split.push_back({g.x0, p.y1, g.x1, g.y1});
    }
    free.resize(kept);
    // Keep only maximal rectangles: a new piece inside another piece or an old rectangle goes;
    // old rectangles cannot lie inside a new piece (the pieces lie inside rectangles that were
    // split, and free rectangles were maximal).
    for (std::size_t i = 0; i < split.size(); ++i) {
      bool inside = false;
      for (std::size_t j = 0; j < split.size() && !inside; ++j) {
        if (j == i || !split[j].contains(split[i])) continue;
        // Equal pieces: keep the first.
        inside = !split[i].contains(split[j]) || j < i;
      }
      for (std::size_t j = 0; j < kept && !inside; ++j) inside = free[j].contains(split[i]);
      if (!inside) free.push_back(split[i]);
    }
  }
  return true;
}

/// Shelves (next fit by decreasing height) in the unit square, for many charts: each item turned
/// to lie flat when turns are allowed, rows filled left to right, the next row on top of the
/// tallest item of the last. Linear after the sort. Returns false when the rows pass the top.
bool pack_shelves(const std::vector<Eigen::Vector2d>& sizes, bool allow_turn,
                  std::vector<Rect>& placed, std::vector<char>& turned) {
  const std::size_t n = sizes.size();
  placed.assign(n, Rect{});
  turned.assign(n, 0);
  std::vector<Eigen::Vector2d> flat(n);
  for (std::size_t i = 0; i < n; ++i) {
    turned[i] = allow_turn && sizes[i].y() > sizes[i].x();
    flat[i] = turned[i] ? Eigen::Vector2d(sizes[i].y(), sizes[i].x()) : sizes[i];
  }
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return flat[a].y() > flat[b].y(); });
  double x = 0, y = 0, row_height = 0;
  for (int item : order) {
    const Eigen::Vector2d& d = flat[item];
    if (d.x() > 1) return false;
    if (x + d.x() > 1) {
      y += row_height;
      x = 0, row_height = 0;
    }
    if (row_height == 0) row_height = d.y();  // the first item of a row is its tallest
    if (y + d.y() > 1) return false;
    placed[item] = Rect{x, y, x + d.x(), y + d.y()};
    x += d.x();
  }
  return true;
}

/// Whether n gutter-sized cells fit in the square as a grid (what a zero scale needs; one row
/// and column spare for the rounding of the cells' coordinates).
bool cells_fit(std::size_t n, double gutter) {
  const double per_side = std::floor(1 / gutter) - 1;
  return per_side * per_side >= static_cast<double>(n);
}

/// Where one chart goes: `turns` quarter turns inside its box (the box of its rotated, scaled
/// layout, of size `box` before turning), then the box's lower-left corner at `corner`.
struct Placement {
  int turns = 0;
  Eigen::Vector2d offset = Eigen::Vector2d::Zero();  ///< of the layout inside its box
  Eigen::Vector2d box = Eigen::Vector2d::Zero();
  Eigen::Vector2d corner = Eigen::Vector2d::Zero();
};

/// A point of the box [0, box.x] x [0, box.y] after `turns` quarter turns, (x, y) -> (H - y, x)
/// each, which keep it in the turned box.
Eigen::Vector2d turn_in_box(Eigen::Vector2d q, int turns, Eigen::Vector2d box) {
  for (int t = 0; t < turns; ++t) {
    q = Eigen::Vector2d(box.y() - q.y(), q.x());
    box = Eigen::Vector2d(box.y(), box.x());
  }
  return q;
}

/// A chart's cells as one span per row, [lo, hi] (lo > hi: an empty row). Filling each row
/// between its first and last cell keeps the masks cheap to test; charts still nest into each
/// other's concavities from above and below.
struct SpanMask {
  int width = 0, height = 0;
  std::vector<int> lo, hi;
  std::vector<int> widest_first;  ///< the non-empty rows, widest span first (they collide first)
  long long cells = 0;
};

/// The atlas as rows of bits (1: taken).
class Occupancy {
 public:
  explicit Occupancy(int side)
      : side_(side), words_((side + 63) / 64), bits_(side * words_, 0), longest_free_(side, side) {}
  int side() const { return side_; }
  /// The longest run of free cells in row y.
  int longest_free(int y) const { return longest_free_[y]; }
  /// The lowest row with a free run of at least `length` cells (side() when none). Runs only
  /// shrink as cells are taken, so each length's answer only moves up: kept per length.
  int lowest_row_with_run(int length) {
    if (length > side_) return side_;
    if (lowest_row_.empty()) lowest_row_.assign(side_ + 1, 0);
    int& y = lowest_row_[length];
    while (y < side_ && longest_free_[y] < length) ++y;
    return y;
  }
  /// First taken cell in [a, b] of row y, or -1.
  int first_taken(int y, int a, int b) const {
    const std::uint64_t* row = &bits_[static_cast<std::size_t>(y) * words_];
    for (int w = a / 64; w <= b / 64; ++w) {
      std::uint64_t word = row[w];
      if (w == a / 64) word &= ~std::uint64_t{0} << (a % 64);
      if (w == b / 64 && b % 64 != 63) word &= (std::uint64_t{1} << (b % 64 + 1)) - 1;
      if (word) return 64 * w + std::countr_zero(word);
    }
    return -1;
  }
  /// First free cell at or after x in row y (side() when none).
  int first_free(int y, int x) const {
    const std::uint64_t* row = &bits_[static_cast<std::size_t>(y) * words_];
    for (int w = x / 64; w < words_; ++w) {
      std::uint64_t word = ~row[w];
      if (w == x / 64) word &= ~std::uint64_t{0} << (x % 64);
      if (word) return std::min(side_, 64 * w + std::countr_zero(word));
    }
    return side_;
  }
  void take(int y, int a, int b) {
    std::uint64_t* row = &bits_[static_cast<std::size_t>(y) * words_];
    for (int x = a; x <= b; ++x) row[x / 64] |= std::uint64_t{1} << (x % 64);
    int longest = 0;
    for (int x = first_free(y, 0); x < side_;) {
      const int end = x < side_ - 1 ? first_taken(y, x, side_ - 1) : -1;
      const int stop = end < 0 ? side_ : end;
      longest = std::max(longest, stop - x);
      x = stop < side_ ? first_free(y, stop) : side_;
    }
    longest_free_[y] = longest;
  }

 private:
  int side_, words_;
  std::vector<std::uint64_t> bits_;
  std::vector<int> longest_free_;
  std::vector<int> lowest_row_;
};

/// Bottom-left first fit of a mask: the lowest row, then the leftmost column, where no row span
/// meets a taken cell, with its top at most max_top. A collision in row j moves the mask to the
/// next free run of that row long enough for its span. `work` counts the rows and positions
/// tried.
bool first_fit(Occupancy& atlas, const SpanMask& m, int max_top, int& at_x, int& at_y,
               long long& work) {
  const int side = atlas.side();
  if (m.width > side || m.height > side || m.widest_first.empty()) return false;
  // The widest row needs a free run as long as its span: no row below the lowest such run.
  const int widest = m.widest_first.front();
  const int start = atlas.lowest_row_with_run(m.hi[widest] - m.lo[widest] + 1) - widest;
  for (int y = std::max(0, start); y + m.height <= std::min(side, max_top); ++y) {
    // Rows without a free run as long as the mask's span there rule the row out at once.
    ++work;
    bool possible = true;
    for (int j = 0; j < m.height && possible; ++j) {
      possible = m.lo[j] > m.hi[j] || atlas.longest_free(y + j) > m.hi[j] - m.lo[j];
    }
    if (!possible) continue;
    int x = 0;
    while (x + m.width <= side) {
      ++work;
      // The first row that collides bounds the next x from below (wide rows collide first).
      int next = -1;
      for (int j : m.widest_first) {
        int taken = atlas.first_taken(y + j, x + m.lo[j], x + m.hi[j]);
        if (taken < 0) continue;
        // Past the taken run, to the next free run of this row long enough for its span.
        const int span = m.hi[j] - m.lo[j] + 1;
        for (;;) {
          const int free = atlas.first_free(y + j, taken);
          if (free + span > side) {
            next = side;
            break;
          }
          taken = atlas.first_taken(y + j, free, free + span - 1);
          if (taken < 0) {
            next = std::max(x + 1, free - m.lo[j]);
            break;
          }
        }
        break;
      }
      if (next < 0) {
        at_x = x, at_y = y;
        return true;
      }
      x = next;
    }
  }
  return false;
}

/// Whether the closed triangle t, grown by margin, meets the closed square [x0, x1] x [y0, y1]:
/// separating axes are the square's and the triangle's edge normals.
bool triangle_meets_square(const std::array<Eigen::Vector2d, 3>& t, bool ccw, double x0, double y0,
                           double x1, double y1, double margin) {
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector2d& p = t[k];
    const Eigen::Vector2d& q = t[(k + 1) % 3];
    // Outward normal of edge p -> q (the interior is on the left when counter-clockwise).
    Eigen::Vector2d n(q.y() - p.y(), p.x() - q.x());
    if (!ccw) n = -n;
    const double length = n.norm();
    if (length == 0) continue;
    // The square's corner deepest inside the edge's half-plane.
    const double x = n.x() > 0 ? x0 : x1, y = n.y() > 0 ? y0 : y1;
    if (n.x() * (x - p.x()) + n.y() * (y - p.y()) > margin * length) return false;
  }
  return true;
}

/// One chart ready to pack: its rotation and its rotated bounding box in layout units.
struct ChartShape {
  double rotation = 0;
  Eigen::Vector2d lo = Eigen::Vector2d::Zero(), hi = Eigen::Vector2d::Zero();
};

/// The grid of the shape packing: cells of side `cell`, `side` of them across the square, each
/// chart grown by `dilation` cells (so that two charts' cells lie 2 dilation cells apart).
struct ShapeGrid {
  double cell = 0;
  int side = 0, dilation = 1;
};

/// The cells of a w x h bitmap (cells of side grid.cell) that the chart's triangles meet, up to
/// kRasterMargin; the chart turned by its rotation, scaled, and moved by `offset` inside the box.
std::vector<char> rasterise(const Points& layout, const Triangles& triangles,
                            const PackedChart& chart, const ChartShape& shape, double scale,
                            const ShapeGrid& grid, const Eigen::Vector2d& offset, int w, int h) {
  const Eigen::Rotation2Dd turn(shape.rotation);
  std::vector<char> bitmap(static_cast<std::size_t>(w) * h, 0);
  for (int f : chart.faces) {
    std::array<Eigen::Vector2d, 3> t;
    for (int k = 0; k < 3; ++k) {
      t[k] = scale * (turn * uv_point(layout, triangles(f, k)) - shape.lo) + offset;
    }
    const bool ccw =
        (t[1] - t[0]).x() * (t[2] - t[0]).y() - (t[1] - t[0]).y() * (t[2] - t[0]).x() >= 0;
    const Eigen::Vector2d lo = t[0].cwiseMin(t[1]).cwiseMin(t[2]);
    const Eigen::Vector2d hi = t[0].cwiseMax(t[1]).cwiseMax(t[2]);
    const int i0 = std::max(0, static_cast<int>(std::floor((lo.x() - kRasterMargin) / grid.cell)));
    const int i1 =
        std::min(w - 1, static_cast<int>(std::floor((hi.x() + kRasterMargin) / grid.cell)));
    const int j0 = std::max(0, static_cast<int>(std::floor((lo.y() - kRasterMargin) / grid.cell)));
    const int j1 =
        std::min(h - 1, static_cast<int>(std::floor((hi.y() + kRasterMargin) / grid.cell)));
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) {
        char& cell = bitmap[static_cast<std::size_t>(j) * w + i];
        if (!cell &&
            triangle_meets_square(t, ccw, i * grid.cell, j * grid.cell, (i + 1) * grid.cell,
                                  (j + 1) * grid.cell, kRasterMargin)) {
          cell = 1;
        }
      }
    }
  }
  return bitmap;
}

/// A w x h bitmap grown by d cells (the chart's cells lie d cells inside its bitmap, so nothing
/// is lost): a square of side 2 d + 1 is a row window then a column window, each a running count.
std::vector<char> dilate(const std::vector<char>& bitmap, int w, int h, int d) {
  auto at = [w](int i, int j) { return static_cast<std::size_t>(j) * w + i; };
  std::vector<char> across(bitmap.size(), 0), grown(bitmap.size(), 0);
  for (int j = 0; j < h; ++j) {
    int count = 0;
    for (int i = 0; i < w + d; ++i) {
      if (i < w) count += bitmap[at(i, j)];
      if (i - 2 * d - 1 >= 0) count -= bitmap[at(i - 2 * d - 1, j)];
      if (i - d >= 0) across[at(i - d, j)] = count > 0;
    }
  }
  for (int i = 0; i < w; ++i) {
    int count = 0;
    for (int j = 0; j < h + d; ++j) {
      if (j < h) count += across[at(i, j)];
      if (j - 2 * d - 1 >= 0) count -= across[at(i, j - 2 * d - 1)];
      if (j - d >= 0) grown[at(i, j - d)] = count > 0;
    }
  }
  return grown;
}

/// The row spans of a w x h bitmap after `turns` quarter turns: (i, j) goes to (h - 1 - j, i)
/// each.
SpanMask span_mask(const std::vector<char>& grown, int w, int h, int turns) {
  SpanMask m;
  const bool swapped = turns % 2 == 1;
  m.width = swapped ? h : w;
  m.height = swapped ? w : h;
  m.lo.assign(m.height, std::numeric_limits<int>::max());
  m.hi.assign(m.height, -1);
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      if (!grown[static_cast<std::size_t>(j) * w + i]) continue;
      int x = i, y = j;
      for (int t = 0, tw = w, th = h; t < turns; ++t) {
        const int nx = th - 1 - y;
        y = x, x = nx;
        std::swap(tw, th);
      }
      m.lo[y] = std::min(m.lo[y], x);
      m.hi[y] = std::max(m.hi[y], x);
    }
  }
  for (int y = 0; y < m.height; ++y) {
    if (m.hi[y] < m.lo[y]) continue;
    m.cells += m.hi[y] - m.lo[y] + 1;
    m.widest_first.push_back(y);
  }
  std::stable_sort(m.widest_first.begin(), m.widest_first.end(),
                   [&](int a, int b) { return m.hi[a] - m.lo[a] > m.hi[b] - m.lo[b]; });
  return m;
}

/// Packs the charts by their shapes at `scale`: each rasterised (every cell its triangles meet,
/// up to a margin that covers the rounding of the placement), grown by the dilation, rows filled
/// between their first and last cell, in each of four quarter turns; placed largest first at the
/// bottom-left first fit of the turn whose top is lowest. False when one does not fit, or when
/// the work counted (first_fit) passes the budget.
bool pack_shapes(const Points& layout, const Triangles& triangles,
                 const std::vector<PackedChart>& charts, const std::vector<ChartShape>& shapes,
                 double scale, const ShapeGrid& grid, bool rotate, long long& work,
                 long long budget, std::vector<Placement>& placement) {
  const int n = static_cast<int>(charts.size());
  const int d = grid.dilation;
  std::vector<std::array<SpanMask, 4>> masks(n);
  std::vector<Placement> base(n);
  for (int c = 0; c < n; ++c) {
    const ChartShape& shape = shapes[c];
    const Eigen::Vector2d size = scale * (shape.hi - shape.lo);
    const int w = static_cast<int>(std::floor(size.x() / grid.cell)) + 1 + 2 * d;
    const int h = static_cast<int>(std::floor(size.y() / grid.cell)) + 1 + 2 * d;
    if (w > grid.side || h > grid.side) return false;
    Placement& p = base[c];
    p.offset = Eigen::Vector2d::Constant(d * grid.cell);
    p.box = Eigen::Vector2d(w * grid.cell, h * grid.cell);
    const std::vector<char> grown = dilate(
        rasterise(layout, triangles, charts[c], shape, scale, grid, p.offset, w, h), w, h, d);
    for (int turns = 0; turns < (rotate ? 4 : 1); ++turns) {
      masks[c][turns] = span_mask(grown, w, h, turns);
    }
  }
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return masks[a][0].cells > masks[b][0].cells; });
  Occupancy atlas(grid.side);
  placement = base;
  for (int c : order) {
    int best_turn = -1, best_x = 0, best_y = 0, best_top = std::numeric_limits<int>::max();
    for (int turns = 0; turns < (rotate ? 4 : 1); ++turns) {
      int x, y;
      // Only a lower top (or the same, further left) can beat the turn found so far.
      if (work > budget) return false;
      if (!first_fit(atlas, masks[c][turns], best_top, x, y, work)) continue;
      const int top = y + masks[c][turns].height;
      if (top < best_top || (top == best_top && x < best_x)) {
        best_turn = turns, best_x = x, best_y = y, best_top = top;
      }
    }
    if (best_turn < 0) return false;
    const SpanMask& m = masks[c][best_turn];
    for (int j = 0; j < m.height; ++j) {
      if (m.lo[j] <= m.hi[j]) atlas.take(best_y + j, best_x + m.lo[j], best_x + m.hi[j]);
    }
    placement[c].turns = best_turn;
    placement[c].corner = Eigen::Vector2d(best_x * grid.cell, best_y * grid.cell);
  }
  return true;
}

/// The charts' faces (face_chart as given, or the connected pieces when it is empty) into
/// out.face_chart and out.charts.
/// \throw InvalidInput for a negative chart index or a chart without faces
void group_faces(const Triangles& triangles, Eigen::Index num_points,
                 const std::vector<int>& face_chart, ChartPacking& out) {
  out.face_chart = face_chart.empty() ? connected_pieces(triangles, num_points) : face_chart;
  int num_charts = 0;
  for (int c : out.face_chart) {
    if (c < 0) throw InvalidInput("pack_charts: negative chart index " + std::to_string(c));
    num_charts = std::max(num_charts, c + 1);
  }
  out.charts.resize(num_charts);
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    out.charts[out.face_chart[f]].faces.push_back(static_cast<int>(f));
  }
  for (int c = 0; c < num_charts; ++c) {
    if (out.charts[c].faces.empty()) {
      throw InvalidInput("pack_charts: chart " + std::to_string(c) + " has no faces");
    }
  }
}

/// Each chart's vertices: those of its faces, in order of first use. A vertex shared by two
/// charts would be placed twice, the last placement kept: a caller's mistake that
/// find_uv_overlaps would not see, so it is refused.
/// \throw InvalidInput for a vertex used by two charts
std::vector<std::vector<int>> vertices_of_charts(const Triangles& triangles,
                                                 Eigen::Index num_points,
                                                 const std::vector<PackedChart>& charts) {
  const int num_charts = static_cast<int>(charts.size());
  std::vector<int> vertex_chart(num_points, -1);
  std::vector<std::vector<int>> chart_vertices(num_charts);
  for (int c = 0; c < num_charts; ++c) {
    for (int f : charts[c].faces) {
      for (int k = 0; k < 3; ++k) {
        const int v = triangles(f, k);
        if (vertex_chart[v] == c) continue;
        if (vertex_chart[v] >= 0) {
          throw InvalidInput("pack_charts: position " + std::to_string(v) + " is used by charts " +
                             std::to_string(vertex_chart[v]) + " and " + std::to_string(c));
        }
        vertex_chart[v] = c;
        chart_vertices[c].push_back(v);
      }
    }
  }
  return chart_vertices;
}

/// Each chart's orientation (that of its minimal-area bounding rectangle when `rotate`, else
/// none) and its box turned so.
std::vector<ChartShape> chart_shapes(const Points& layout,
                                     const std::vector<std::vector<int>>& chart_vertices,
                                     bool rotate) {
  std::vector<ChartShape> shapes(chart_vertices.size());
  for (std::size_t c = 0; c < chart_vertices.size(); ++c) {
    ChartShape& shape = shapes[c];
    if (rotate) {
      std::vector<Eigen::Vector2d> points;
      points.reserve(chart_vertices[c].size());
      for (int v : chart_vertices[c]) points.push_back(uv_point(layout, v));
      shape.rotation = minimal_rectangle_rotation(convex_hull(std::move(points)));
    }
    const Eigen::Rotation2Dd turn(shape.rotation);
    shape.lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
    shape.hi = -shape.lo;
    for (int v : chart_vertices[c]) {
      const Eigen::Vector2d q = turn * uv_point(layout, v);
      shape.lo = shape.lo.cwiseMin(q), shape.hi = shape.hi.cwiseMax(q);
    }
  }
  return shapes;
}

/// The longest side of the charts' boxes (layout units).
double longest_side(const std::vector<ChartShape>& shapes) {
  double longest = 0;
  for (const ChartShape& s : shapes) longest = std::max(longest, (s.hi - s.lo).maxCoeff());
  return longest;
}

/// The item orders the rectangle packer tries at each scale (it is greedy: one order may fail
/// where another fits): by decreasing longest side, area, shortest side and perimeter of the
/// box, ties in chart order.
std::vector<std::vector<int>> rectangle_orders(const std::vector<ChartShape>& shapes) {
  std::vector<std::vector<int>> orders;
  std::vector<int> base(shapes.size());
  std::iota(base.begin(), base.end(), 0);
  auto by = [&](auto key) {
    std::vector<int> order = base;
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return key(a) > key(b); });
    orders.push_back(std::move(order));
  };
  auto size = [&](int c) -> Eigen::Vector2d { return shapes[c].hi - shapes[c].lo; };
  by([&](int c) { return size(c).maxCoeff(); });
  by([&](int c) { return size(c).prod(); });
  by([&](int c) { return size(c).minCoeff(); });
  by([&](int c) { return size(c).sum(); });
  return orders;
}

/// The charts packed in their rectangles, each grown by the gutter: the largest common scale at
/// which they fit, known to the relative `tolerance`, and where each chart goes at it. Upper
/// bound: the rectangles' total area, and the longest side, must fit in the square. Then down by
/// steps of kScaleStepDown to a scale that fits (rectangle packings usually fill 70 to 95% of the
/// square), and bisection between it and the last that did not. `attempts` counts the packings.
/// \throw SolverError when they do not fit even at zero size (cells_fit(gutter) rules it out)
double pack_by_rectangles(const std::vector<ChartShape>& shapes, double gutter, double tolerance,
                          bool rotate, int& attempts, std::vector<Placement>& placement) {
  const int num_charts = static_cast<int>(shapes.size());
  double box_area = 0;
  for (const ChartShape& s : shapes) {
    const Eigen::Vector2d d = s.hi - s.lo;
    box_area += d.x() * d.y();
  }
  const double longest = longest_side(shapes);
  const std::vector<std::vector<int>> orders = rectangle_orders(shapes);
  std::vector<Eigen::Vector2d> padded(num_charts);
  std::vector<Rect> placed, best_placed;
  std::vector<char> turned, best_turned;
  auto fits = [&](double scale) {
    for (int c = 0; c < num_charts; ++c) {
      padded[c] = scale * (shapes[c].hi - shapes[c].lo) + Eigen::Vector2d::Constant(gutter);
    }
    if (num_charts > kShelvesAbove) {
      ++attempts;
      return pack_shelves(padded, rotate, placed, turned);
    }
    for (const std::vector<int>& order : orders) {
      ++attempts;
      if (pack_rectangles(padded, order, rotate, placed, turned)) return true;
    }
    return false;
  };
  double high = longest > 0 ? (1 - gutter) / longest : 1.0;
  if (box_area > 0) high = std::min(high, 1 / std::sqrt(box_area));
  double low = high;
  bool found = false;
  for (int step = 0; step < kScaleStepsDown && !found; ++step) {
    found = fits(low);
    if (!found) high = low, low *= kScaleStepDown;
  }
  if (!found) {
    low = 0;
    if (!fits(0)) {
      throw SolverError("pack_charts: " + std::to_string(num_charts) +
                        " charts do not fit even at zero size");  // cells_fit guarantees they do
    }
  }
  best_placed = placed, best_turned = turned;
  while (low < high && high - low > tolerance * high) {
    const double mid = 0.5 * (low + high);
    if (fits(mid)) {
      low = mid;
      best_placed = placed, best_turned = turned;
    } else {
      high = mid;
    }
  }
  placement.assign(num_charts, Placement{});
  for (int c = 0; c < num_charts; ++c) {
    placement[c].turns = static_cast<unsigned char>(best_turned[c]);  // 0..3 quarter turns
    placement[c].box = low * (shapes[c].hi - shapes[c].lo);
    placement[c].corner = Eigen::Vector2d(best_placed[c].x0, best_placed[c].y0) +
                          Eigen::Vector2d::Constant(gutter / 2);
  }
  return low;
}

/// The grid of the shape packing: cells of about 1 / resolution, two dilations wide exactly the
/// gutter when it is wider.
ShapeGrid shape_grid(double gutter, int resolution) {
  ShapeGrid grid;
  const double target = 1.0 / resolution;
  grid.dilation = std::max(1, static_cast<int>(std::lround(gutter / (2 * target))));
  grid.cell = gutter >= 2 * target ? gutter / (2 * grid.dilation) : target;
  grid.side = static_cast<int>(std::floor(1 / grid.cell));
  return grid;
}

/// The charts packed by their shapes on a grid: worth it when charts leave their rectangles
/// partly empty. Searched like the rectangles' scale, from the rectangles' scale up to the
/// charts' own area bound; `scale` and `placement` are replaced (and out.by_shape set) only when
/// the shapes do better. Adds to out.packing_attempts, sets out.raster_work.
void pack_by_shapes(const Points& layout, const Triangles& triangles,
                    const std::vector<ChartShape>& shapes, double gutter, double tolerance,
                    const ChartPackingOptions& options, double& scale,
                    std::vector<Placement>& placement, ChartPacking& out) {
  const ShapeGrid grid = shape_grid(gutter, options.raster_resolution);
  double chart_area = 0;
  for (const PackedChart& chart : out.charts) {
    for (int f : chart.faces) chart_area += 0.5 * std::abs(twice_area(layout, triangles, f));
  }
  const double longest = longest_side(shapes);
  double bound = longest > 0 ? 1 / longest : 1.0;
  if (chart_area > 0) bound = std::min(bound, 1 / std::sqrt(chart_area));
  std::vector<Placement> shaped;
  long long work = 0;
  const long long budget = options.raster_work_limit;
  auto shapes_fit = [&](double s) {
    ++out.packing_attempts;
    return pack_shapes(layout, triangles, out.charts, shapes, s, grid, options.rotate, work, budget,
                       shaped);
  };
  // A scale where the shapes fit: the rectangles' (or a little less: a tight rectangle packing
  // can leave no room for the cells a shape's outline and gutter round up to). Then up by steps
  // of kShapeStepUp while they fit, then bisection; the work limit stops the search with the
  // best packing found so far. The shapes are kept only when they beat the rectangles.
  double shape_low = std::min(scale, bound);
  bool fit = false;
  for (int step = 0; step < kShapeStartTries && !fit && work <= budget;
       ++step, shape_low *= kShapeStartStepDown) {
    fit = shapes_fit(shape_low);
    if (fit) break;
  }
  // Found below the rectangles' scale: worth going on only if the shapes also fit above it.
  if (fit && shape_low < scale) {
    shape_low = scale * (1 + tolerance);
    fit = shape_low < bound && work <= budget && shapes_fit(shape_low);
  }
  if (fit) {
    std::vector<Placement> best = shaped;
    double shape_high = bound;
    for (double s = shape_low * kShapeStepUp; work <= budget; s *= kShapeStepUp) {
      if (s >= bound || !shapes_fit(s)) {
        shape_high = std::min(s, bound);
        break;
      }
      shape_low = s;
      best = shaped;
    }
    while (work <= budget && shape_high - shape_low > tolerance * shape_high) {
      const double mid = 0.5 * (shape_low + shape_high);
      if (shapes_fit(mid)) {
        shape_low = mid;
        best = shaped;
      } else {
        shape_high = mid;
      }
    }
    if (shape_low > scale) {
      scale = shape_low;
      placement = std::move(best);
      out.by_shape = true;
    }
  }
  out.raster_work = work;
}

/// Places the charts: each turned by its rotation, scaled by out.scale, turned by the packer's
/// quarter turns inside its box, the box moved to its corner. Fills out.uv and per chart its
/// rotation, translation, box and area, and the coverages.
void place_charts(const Points& layout, const Triangles& triangles,
                  const std::vector<ChartShape>& shapes,
                  const std::vector<std::vector<int>>& chart_vertices,
                  const std::vector<Placement>& placement, ChartPacking& out) {
  out.uv = Points::Zero(layout.rows(), 2);
  for (std::size_t c = 0; c < out.charts.size(); ++c) {
    PackedChart& chart = out.charts[c];
    const ChartShape& shape = shapes[c];
    const Placement& p = placement[c];
    chart.rotation = shape.rotation + p.turns * std::numbers::pi / 2;
    const Eigen::Rotation2Dd rotation(shape.rotation);
    for (int v : chart_vertices[c]) {
      const Eigen::Vector2d q = out.scale * (rotation * uv_point(layout, v) - shape.lo) + p.offset;
      out.uv.row(v) = (p.corner + turn_in_box(q, p.turns, p.box)).transpose();
    }
    // uv = scale R(rotation) p + translation: read the translation off the map of the origin.
    chart.translation = p.corner + turn_in_box(-out.scale * shape.lo + p.offset, p.turns, p.box);
    chart.box_min = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
    chart.box_max = -chart.box_min;
    for (int v : chart_vertices[c]) {
      chart.box_min = chart.box_min.cwiseMin(uv_point(out.uv, v));
      chart.box_max = chart.box_max.cwiseMax(uv_point(out.uv, v));
    }
    for (int f : chart.faces) chart.area += 0.5 * std::abs(twice_area(out.uv, triangles, f));
    out.coverage += chart.area;
    out.rectangle_coverage += (out.scale * (shape.hi - shape.lo)).prod();
  }
}

}  // namespace

ChartPacking pack_charts(const Points& layout, const Triangles& triangles,
                         const std::vector<int>& face_chart, const ChartPackingOptions& options) {
  const auto start = Clock::now();
  check_uv_input("pack_charts", layout, triangles, face_chart, "face_chart");
  if (triangles.rows() == 0) throw InvalidInput("pack_charts: no faces");
  if (!(options.gutter >= 0 && options.gutter < 0.5)) {
    throw InvalidInput("pack_charts: gutter " + std::to_string(options.gutter) +
                       " is not in [0, 0.5)");
  }
  ChartPacking out;
  group_faces(triangles, layout.rows(), face_chart, out);
  const std::vector<std::vector<int>> chart_vertices =
      vertices_of_charts(triangles, layout.rows(), out.charts);
  const std::vector<ChartShape> shapes = chart_shapes(layout, chart_vertices, options.rotate);
  double gutter = std::max(options.gutter, kMinGutter);
  while (!cells_fit(out.charts.size(), gutter)) gutter /= 2;
  const double tolerance = std::max(options.scale_tolerance, kMinScaleTolerance);
  std::vector<Placement> placement;
  double scale = pack_by_rectangles(shapes, gutter, tolerance, options.rotate, out.packing_attempts,
                                    placement);
  if (options.raster_resolution > 0) {
    pack_by_shapes(layout, triangles, shapes, gutter, tolerance, options, scale, placement, out);
  }
  out.scale = scale;
  out.gutter = gutter;
  place_charts(layout, triangles, shapes, chart_vertices, placement, out);
  out.overlapping_face_pairs = find_uv_overlaps(out.uv, triangles, out.face_chart, 0).count;
  out.seconds = seconds_since(start);
  return out;
}

}  // namespace ricci
