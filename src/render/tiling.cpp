#include "ricci/render/tiling.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <map>
#include <numbers>
#include <string>
#include <unordered_map>

#include "cairo_support.hpp"
#include "ricci/errors.hpp"

namespace ricci {
namespace {

using Complex = std::complex<double>;
using DiskPoints = Eigen::Matrix<double, Eigen::Dynamic, 2>;
using render_detail::set_colour;

/// Fill colours of the images, cycled by word length or last generator.
const Rgb kPalette[] = {{0.55, 0.71, 0.90}, {0.60, 0.85, 0.62}, {0.97, 0.80, 0.45},
                        {0.82, 0.66, 0.90}, {0.95, 0.62, 0.62}, {0.55, 0.85, 0.85},
                        {0.85, 0.85, 0.50}, {0.75, 0.75, 0.95}};
constexpr int kPaletteSize = sizeof(kPalette) / sizeof(kPalette[0]);

/// One image g(D): its boundary loops in pixels and what colours it.
struct Tile {
  std::vector<std::vector<Eigen::Vector2d>> loops;
  int length = 0;
  int last = 0;
  double diameter = 0;  ///< pixels
};

struct TilingDrawing {
  double centre = 0, radius = 0;        ///< unit disk -> pixels
  std::vector<std::vector<int>> loops;  ///< the domain's boundary loops (vertex indices)
  std::vector<Tile> tiles;
  TilingInfo info;

  Eigen::Vector2d to_pixel(Complex z) const {
    return {centre + radius * z.real(), centre - radius * z.imag()};
  }
};

/// The boundary of the union of the triangles: directed edges u -> v without v -> u, chained into
/// closed loops (at a vertex with several outgoing boundary edges any unused one continues: the
/// loops still bound the union under the non-zero winding rule).
std::vector<std::vector<int>> boundary_loops(const Triangles& triangles, int num_vertices) {
  std::map<std::pair<int, int>, int> directed;
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    for (int k = 0; k < 3; ++k) ++directed[{triangles(f, k), triangles(f, (k + 1) % 3)}];
  }
  std::vector<std::vector<int>> outgoing(num_vertices);
  for (const auto& [edge, count] : directed) {
    const auto twin = directed.find({edge.second, edge.first});
    const int twins = twin == directed.end() ? 0 : twin->second;
    for (int k = twins; k < count; ++k) outgoing[edge.first].push_back(edge.second);
  }
  std::vector<std::vector<int>> loops;
  for (int start = 0; start < num_vertices; ++start) {
    while (!outgoing[start].empty()) {
      std::vector<int> loop = {start};
      int v = start;
      while (true) {
        const int next = outgoing[v].back();
        outgoing[v].pop_back();
        if (next == start) break;
        loop.push_back(next);
        v = next;
        if (outgoing[v].empty()) break;  // cannot happen for closed boundaries
      }
      loops.push_back(std::move(loop));
    }
  }
  return loops;
}

/// A set of points of the disk, equal within `tolerance`, on a hash grid.
class PointSet {
 public:
  explicit PointSet(double tolerance) : tolerance_(tolerance) {}

  /// Adds z unless a point within the tolerance is there; returns whether it was added.
  bool insert(Complex z) {
    const long long cx = cell(z.real()), cy = cell(z.imag());
    for (long long dx = -1; dx <= 1; ++dx) {
      for (long long dy = -1; dy <= 1; ++dy) {
        const auto found = cells_.find(key(cx + dx, cy + dy));
        if (found == cells_.end()) continue;
        for (Complex w : found->second) {
          if (std::abs(w - z) < tolerance_) return false;
        }
      }
    }
    cells_[key(cx, cy)].push_back(z);
    return true;
  }

 private:
  long long cell(double x) const { return static_cast<long long>(std::floor(x / tolerance_)); }
  static long long key(long long x, long long y) { return x * 4000003LL + y; }
  double tolerance_;
  std::unordered_map<long long, std::vector<Complex>> cells_;
};

TilingDrawing prepare(const char* fn, const DiskPoints& positions, const Triangles& triangles,
                      const std::vector<Mobius>& generators, const TilingOptions& options) {
  const std::string name(fn);
  render_detail::check_picture_size(fn, options.size, options.size, 16);
  if (options.max_word_length < 0 || options.max_images < 0 || !(options.min_image_pixels >= 0) ||
      !(options.outline_width >= 0) || !(options.edge_width >= 0)) {
    throw InvalidInput(name +
                       ": max_word_length, max_images, min_image_pixels, outline_width "
                       "and edge_width must be >= 0");
  }
  if (triangles.rows() == 0) throw InvalidInput(name + ": there are no triangles");
  const int nv = static_cast<int>(positions.rows());
  for (int v = 0; v < nv; ++v) {
    const Complex z(positions(v, 0), positions(v, 1));
    if (!positions.row(v).allFinite() || !(std::abs(z) < 1.0)) {
      throw InvalidInput(name + ": position " + std::to_string(v) +
                         " is not a finite point inside the unit circle");
    }
  }
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      if (triangles(f, k) < 0 || triangles(f, k) >= nv) {
        throw InvalidInput(name + ": triangle " + std::to_string(f) + " has vertex index " +
                           std::to_string(triangles(f, k)) + " outside [0, " + std::to_string(nv) +
                           ")");
      }
    }
  }
  std::vector<Mobius> letters;  // generator i at 2 i, its inverse at 2 i + 1
  for (std::size_t i = 0; i < generators.size(); ++i) {
    const double det = determinant(generators[i]);
    if (!(det > 0) || !std::isfinite(det)) {
      throw InvalidInput(name + ": generator " + std::to_string(i) + " has determinant " +
                         std::to_string(det) + " (must be positive)");
    }
    letters.push_back(normalized(generators[i]));
    letters.push_back(inverse(letters.back()));
  }

  TilingDrawing d;
  const double margin = std::max(2.0, 0.02 * options.size);
  d.centre = 0.5 * options.size;
  d.radius = 0.5 * options.size - margin;
  d.loops = boundary_loops(triangles, nv);
  d.info.boundary_loops = static_cast<int>(d.loops.size());
  std::vector<Complex> boundary;  // every boundary vertex once per loop
  for (const auto& loop : d.loops) {
    for (int v : loop) boundary.emplace_back(positions(v, 0), positions(v, 1));
  }
  if (boundary.empty()) throw InvalidInput(name + ": the triangles have no boundary");

  // Reference point: the centroid of the largest triangle, inside the domain, so that distinct
  // group elements move it to distinct points.
  Eigen::Index largest = 0;
  double largest_area = -1;
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    const Eigen::Vector2d a = positions.row(triangles(f, 0));
    const Eigen::Vector2d e1 = Eigen::Vector2d(positions.row(triangles(f, 1))) - a;
    const Eigen::Vector2d e2 = Eigen::Vector2d(positions.row(triangles(f, 2))) - a;
    const double area = std::abs(e1.x() * e2.y() - e1.y() * e2.x());
    if (area > largest_area) {
      largest_area = area;
      largest = f;
    }
  }
  Complex reference = 0;
  for (int k = 0; k < 3; ++k) {
    reference += Complex(positions(triangles(largest, k), 0), positions(triangles(largest, k), 1));
  }
  reference /= 3.0;

  // Breadth first over reduced words; an element is known by its image of the reference point
  // (images below the pixel threshold are never expanded, so the points kept are at least a few
  // pixels from the circle, where distinct orbit points are far apart compared to this).
  constexpr double kSameOrbitPoint = 1e-9;
  PointSet seen(kSameOrbitPoint);
  seen.insert(reference);
  struct Element {
    Mobius map;
    int length = 0;
    int last = -1;
  };
  std::deque<Element> queue = {Element{}};
  while (!queue.empty() && !d.info.reached_max_images) {
    const Element e = queue.front();
    queue.pop_front();
    if (e.length >= options.max_word_length) continue;
    for (int t = 0; t < static_cast<int>(letters.size()); ++t) {
      if (e.last >= 0 && t == (e.last ^ 1)) continue;  // g g^-1
      const Mobius map = compose(e.map, letters[t]);
      if (!seen.insert(apply_mobius(map, reference))) {
        ++d.info.duplicates;
        continue;
      }
      Tile tile;
      tile.length = e.length + 1;
      tile.last = t / 2;
      Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e300), hi = -lo;
      std::size_t at = 0;
      for (const auto& loop : d.loops) {
        std::vector<Eigen::Vector2d> pixels;
        pixels.reserve(loop.size());
        for (std::size_t k = 0; k < loop.size(); ++k) {
          pixels.push_back(d.to_pixel(apply_mobius(map, boundary[at++])));
          lo = lo.cwiseMin(pixels.back());
          hi = hi.cwiseMax(pixels.back());
        }
        tile.loops.push_back(std::move(pixels));
      }
      tile.diameter = (hi - lo).norm();
      if (tile.diameter < options.min_image_pixels) {
        ++d.info.images_too_small;
        continue;
      }
      d.info.longest_word = tile.length;
      d.tiles.push_back(std::move(tile));
      queue.push_back({map, e.length + 1, t});
      if (static_cast<int>(d.tiles.size()) >= options.max_images) {
        d.info.reached_max_images = true;
        break;
      }
    }
  }
  d.info.images_drawn = static_cast<int>(d.tiles.size());
  return d;
}

void trace_loops(cairo_t* cr, const std::vector<std::vector<Eigen::Vector2d>>& loops) {
  for (const auto& loop : loops) {
    for (std::size_t k = 0; k < loop.size(); ++k) {
      if (k == 0) {
        render_detail::cairo_api().move_to(cr, loop[k].x(), loop[k].y());
      } else {
        render_detail::cairo_api().line_to(cr, loop[k].x(), loop[k].y());
      }
    }
    render_detail::cairo_api().close_path(cr);
  }
}

void draw(cairo_t* cr, const TilingDrawing& d, const DiskPoints& positions,
          const Triangles& triangles, const TilingOptions& options) {
  set_colour(cr, options.background);
  render_detail::cairo_api().paint(cr);
  render_detail::cairo_api().set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  render_detail::cairo_api().set_fill_rule(cr, CAIRO_FILL_RULE_WINDING);
  render_detail::cairo_api().arc(cr, d.centre, d.centre, d.radius, 0, 2 * std::numbers::pi);
  set_colour(cr, options.disk_colour);
  render_detail::cairo_api().fill(cr);

  for (const Tile& tile : d.tiles) {
    trace_loops(cr, tile.loops);
    const int index = options.colour_by_last_generator ? tile.last : tile.length - 1;
    set_colour(cr, kPalette[index % kPaletteSize]);
    render_detail::cairo_api().fill_preserve(cr);
    render_detail::cairo_api().set_line_width(
        cr, std::min(options.outline_width, 0.05 * tile.diameter));
    set_colour(cr, {0.2, 0.2, 0.25});
    render_detail::cairo_api().stroke(cr);
  }

  // The domain: filled and outlined, then its mesh edges.
  std::vector<std::vector<Eigen::Vector2d>> domain;
  for (const auto& loop : d.loops) {
    std::vector<Eigen::Vector2d> pixels;
    pixels.reserve(loop.size());
    for (int v : loop) pixels.push_back(d.to_pixel({positions(v, 0), positions(v, 1)}));
    domain.push_back(std::move(pixels));
  }
  trace_loops(cr, domain);
  set_colour(cr, options.domain_colour);
  render_detail::cairo_api().fill_preserve(cr);
  render_detail::cairo_api().set_line_width(cr, 2 * options.outline_width);
  set_colour(cr, {0.1, 0.05, 0.0});
  render_detail::cairo_api().stroke(cr);
  if (options.draw_mesh_edges && options.edge_width > 0) {
    for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
      for (int k = 0; k < 3; ++k) {
        const int u = triangles(f, k), v = triangles(f, (k + 1) % 3);
        if (u > v) continue;  // interior edges once (boundary edges u > v are outlined anyway)
        const Eigen::Vector2d a = d.to_pixel({positions(u, 0), positions(u, 1)});
        const Eigen::Vector2d b = d.to_pixel({positions(v, 0), positions(v, 1)});
        render_detail::cairo_api().move_to(cr, a.x(), a.y());
        render_detail::cairo_api().line_to(cr, b.x(), b.y());
      }
    }
    render_detail::cairo_api().set_line_width(cr, options.edge_width);
    set_colour(cr, {0.3, 0.15, 0.05}, 0.35);
    render_detail::cairo_api().stroke(cr);
  }

  render_detail::cairo_api().arc(cr, d.centre, d.centre, d.radius, 0, 2 * std::numbers::pi);
  render_detail::cairo_api().set_line_width(cr, 1.5);
  set_colour(cr, {0.1, 0.1, 0.1});
  render_detail::cairo_api().stroke(cr);
}

}  // namespace

Image draw_tiling(const DiskPoints& positions, const Triangles& triangles,
                  const std::vector<Mobius>& generators, const TilingOptions& options,
                  TilingInfo* info) {
  const TilingDrawing d = prepare("draw_tiling", positions, triangles, generators, options);
  Image image = make_image(options.size, options.size, options.background);
  render_detail::draw_on_image(image,
                               [&](cairo_t* cr) { draw(cr, d, positions, triangles, options); });
  if (info) *info = d.info;
  return image;
}

std::string draw_tiling_svg(const DiskPoints& positions, const Triangles& triangles,
                            const std::vector<Mobius>& generators, const TilingOptions& options,
                            TilingInfo* info) {
  const TilingDrawing d = prepare("draw_tiling_svg", positions, triangles, generators, options);
  std::string svg = render_detail::draw_svg(
      options.size, options.size, [&](cairo_t* cr) { draw(cr, d, positions, triangles, options); });
  if (info) *info = d.info;
  return svg;
}

}  // namespace ricci
