#include "ricci/param/atlas/uv_overlaps.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "param/atlas/detail/uv_input.hpp"
#include "ricci/numerics/predicates.hpp"

namespace ricci {
namespace {

using atlas_detail::Points;

/// The overlap grid's cell never goes below this (uv units), so that dividing by it stays finite
/// however small the faces (the smallest normal double is 2e-308).
constexpr double kMinOverlapCell = 1e-300;

}  // namespace

UvOverlaps find_uv_overlaps(const Points& uv, const Triangles& triangles,
                            const std::vector<int>& face_group, int max_pairs) {
  atlas_detail::check_uv_input("find_uv_overlaps", uv, triangles, face_group, "face_group");
  UvOverlaps out;
  const Eigen::Index nf = triangles.rows();
  // Each face with an interior, counter-clockwise, with its box.
  struct Face {
    std::array<Eigen::Vector2d, 3> p;
    Eigen::Vector2d lo, hi;
  };
  std::vector<Face> faces(nf);
  std::vector<char> solid(nf, 0);
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  double extent_sum = 0;
  int num_solid = 0;
  for (Eigen::Index f = 0; f < nf; ++f) {
    Face& face = faces[f];
    for (int k = 0; k < 3; ++k) face.p[k] = atlas_detail::uv_point(uv, triangles(f, k));
    const int sign = orientation_sign(face.p[0], face.p[1], face.p[2]);
    if (sign == 0) continue;
    if (sign < 0) std::swap(face.p[1], face.p[2]);
    solid[f] = 1;
    ++num_solid;
    face.lo = face.p[0].cwiseMin(face.p[1]).cwiseMin(face.p[2]);
    face.hi = face.p[0].cwiseMax(face.p[1]).cwiseMax(face.p[2]);
    lo = lo.cwiseMin(face.lo), hi = hi.cwiseMax(face.hi);
    extent_sum += (face.hi - face.lo).maxCoeff();
  }
  if (num_solid < 2) return out;
  // Grid cells about twice the mean face extent: a face touches a few cells, a cell holds a few
  // faces.
  const double cell = std::max(2 * extent_sum / num_solid, kMinOverlapCell);
  const Eigen::Vector2d span = (hi - lo) / cell;
  const long long max_cells = 4LL * num_solid + 16;
  const double shrink = std::max(1.0, std::sqrt((span.x() + 1) * (span.y() + 1) / max_cells));
  const double size = cell * shrink;
  const int nx = static_cast<int>(std::min(span.x() / shrink, 1e9)) + 1;
  const int ny = static_cast<int>(std::min(span.y() / shrink, 1e9)) + 1;
  auto cell_of = [&](double x, double origin, int n) {
    return std::clamp(static_cast<int>((x - origin) / size), 0, n - 1);
  };
  std::vector<std::vector<int>> grid(static_cast<std::size_t>(nx) * ny);
  for (Eigen::Index f = 0; f < nf; ++f) {
    if (!solid[f]) continue;
    const Face& face = faces[f];
    for (int i = cell_of(face.lo.x(), lo.x(), nx); i <= cell_of(face.hi.x(), lo.x(), nx); ++i) {
      for (int j = cell_of(face.lo.y(), lo.y(), ny); j <= cell_of(face.hi.y(), lo.y(), ny); ++j) {
        grid[static_cast<std::size_t>(j) * nx + i].push_back(static_cast<int>(f));
      }
    }
  }
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const std::vector<int>& here = grid[static_cast<std::size_t>(j) * nx + i];
      for (std::size_t s = 0; s < here.size(); ++s) {
        for (std::size_t t = s + 1; t < here.size(); ++t) {
          const int fa = std::min(here[s], here[t]), fb = std::max(here[s], here[t]);
          if (!face_group.empty() && face_group[fa] == face_group[fb]) continue;
          const Face& a = faces[fa];
          const Face& b = faces[fb];
          if (a.hi.x() < b.lo.x() || b.hi.x() < a.lo.x() || a.hi.y() < b.lo.y() ||
              b.hi.y() < a.lo.y()) {
            continue;
          }
          // Test each pair once: in the cell holding the low corner of their boxes' overlap.
          const double x = std::max(a.lo.x(), b.lo.x()), y = std::max(a.lo.y(), b.lo.y());
          if (cell_of(x, lo.x(), nx) != i || cell_of(y, lo.y(), ny) != j) continue;
          if (!ccw_triangles_overlap(a.p, b.p)) continue;
          if (static_cast<int>(out.pairs.size()) < max_pairs) out.pairs.push_back({fa, fb});
          ++out.count;
        }
      }
    }
  }
  std::sort(out.pairs.begin(), out.pairs.end());
  return out;
}

}  // namespace ricci
