#include "ricci/match/point_location.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Geometry>

#include "ricci/errors.hpp"

namespace ricci {
namespace {

constexpr double kInsideTolerance = 1e-9;

void check_locator_faces(const Triangles& triangles, Eigen::Index num_points, const char* what) {
  if (triangles.rows() == 0)
    throw InvalidInput(std::string(what) + ": no faces to locate points in");
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      if (triangles(f, k) < 0 || triangles(f, k) >= num_points) {
        throw InvalidInput(std::string(what) + ": face " + std::to_string(f) + " has vertex " +
                           std::to_string(triangles(f, k)) + ", out of range");
      }
    }
  }
}

// Counting sort of (cell, face) pairs into the CSR arrays start / faces.
template <class ForEachCell>
void bucket_faces(int num_cells, Eigen::Index num_faces, ForEachCell for_each_cell,
                  std::vector<int>& start, std::vector<int>& faces) {
  start.assign(static_cast<std::size_t>(num_cells) + 1, 0);
  for (Eigen::Index f = 0; f < num_faces; ++f) for_each_cell(f, [&](int c) { ++start[c + 1]; });
  for (int c = 0; c < num_cells; ++c) start[c + 1] += start[c];
  faces.assign(static_cast<std::size_t>(start.back()), -1);
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (Eigen::Index f = 0; f < num_faces; ++f) {
    for_each_cell(f, [&](int c) { faces[fill[c]++] = static_cast<int>(f); });
  }
}

// Keeps the candidate whose smallest raw weight is largest (the face the point is deepest in,
// or nearest to when it is in none).
struct Best {
  int face = -1;
  Eigen::Vector3d raw = Eigen::Vector3d::Zero();
  double score = -std::numeric_limits<double>::infinity();
  void offer(int f, const Eigen::Vector3d& w) {
    if (!w.allFinite()) return;
    const double s = w.minCoeff();
    if (s > score) {
      score = s;
      face = f;
      raw = w;
    }
  }
  bool inside() const { return score >= -kInsideTolerance; }
  FaceLocation result() const {
    FaceLocation location;
    location.face = face;
    if (face < 0) return location;
    location.inside = inside();
    location.outside_by = location.inside ? 0.0 : -score;
    Eigen::Vector3d w = raw.cwiseMax(0.0);
    const double sum = w.sum();
    location.weights =
        sum > 0 ? Eigen::Vector3d(w / sum) : Eigen::Vector3d(1.0 / 3, 1.0 / 3, 1.0 / 3);
    return location;
  }
};

}  // namespace

PlanarLocator::PlanarLocator(const Eigen::Matrix<double, Eigen::Dynamic, 2>& points,
                             const Triangles& triangles)
    : points_(points), triangles_(triangles) {
  check_locator_faces(triangles, points.rows(), "PlanarLocator");
  if (!points.allFinite()) throw InvalidInput("PlanarLocator: a point is not finite");
  lower_ = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  upper_ = -lower_;
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      lower_ = lower_.cwiseMin(points.row(triangles(f, k)).transpose());
      upper_ = upper_.cwiseMax(points.row(triangles(f, k)).transpose());
    }
  }
  const Eigen::Vector2d extent = (upper_ - lower_).cwiseMax(1e-300);
  // About one face per cell, at most 2048 cells a side.
  cell_size_ = std::sqrt(extent.x() * extent.y() / static_cast<double>(triangles.rows()));
  cell_size_ = std::max({cell_size_, extent.maxCoeff() / 2048, 1e-300});
  nx_ = std::clamp(static_cast<int>(std::ceil(extent.x() / cell_size_)), 1, 2048);
  ny_ = std::clamp(static_cast<int>(std::ceil(extent.y() / cell_size_)), 1, 2048);
  const auto cell_range = [&](double lo, double hi, double origin, int n) {
    const int a = std::clamp(static_cast<int>(std::floor((lo - origin) / cell_size_)), 0, n - 1);
    const int b = std::clamp(static_cast<int>(std::floor((hi - origin) / cell_size_)), 0, n - 1);
    return std::pair<int, int>{a, b};
  };
  bucket_faces(
      nx_ * ny_, triangles.rows(),
      [&](Eigen::Index f, auto&& add) {
        Eigen::Vector2d lo = points.row(triangles(f, 0)).transpose(), hi = lo;
        for (int k = 1; k < 3; ++k) {
          lo = lo.cwiseMin(points.row(triangles(f, k)).transpose());
          hi = hi.cwiseMax(points.row(triangles(f, k)).transpose());
        }
        const auto [x0, x1] = cell_range(lo.x(), hi.x(), lower_.x(), nx_);
        const auto [y0, y1] = cell_range(lo.y(), hi.y(), lower_.y(), ny_);
        for (int y = y0; y <= y1; ++y) {
          for (int x = x0; x <= x1; ++x) add(cell_index(x, y));
        }
      },
      cell_start_, cell_faces_);
}

Eigen::Vector3d PlanarLocator::raw_weights(int face, const Eigen::Vector2d& p) const {
  const Eigen::Vector2d a = points_.row(triangles_(face, 0)).transpose();
  const Eigen::Vector2d b = points_.row(triangles_(face, 1)).transpose();
  const Eigen::Vector2d c = points_.row(triangles_(face, 2)).transpose();
  const auto cross = [](const Eigen::Vector2d& u, const Eigen::Vector2d& v) {
    return u.x() * v.y() - u.y() * v.x();
  };
  const double area = cross(b - a, c - a);
  if (!(std::abs(area) > 0))
    return Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  return Eigen::Vector3d(cross(b - p, c - p), cross(c - p, a - p), cross(a - p, b - p)) / area;
}

FaceLocation PlanarLocator::locate(const Eigen::Vector2d& point) const {
  const int cx =
      std::clamp(static_cast<int>(std::floor((point.x() - lower_.x()) / cell_size_)), 0, nx_ - 1);
  const int cy =
      std::clamp(static_cast<int>(std::floor((point.y() - lower_.y()) / cell_size_)), 0, ny_ - 1);
  Best best;
  // Rings of cells around the point's: stop at the first ring with a face holding the point, or
  // two rings after the first that had any face (the nearest face is then among those seen).
  int found_ring = -1;
  const int max_ring = std::max(nx_, ny_);
  for (int ring = 0; ring <= max_ring; ++ring) {
    bool any = false;
    for (int y = cy - ring; y <= cy + ring; ++y) {
      if (y < 0 || y >= ny_) continue;
      for (int x = cx - ring; x <= cx + ring; ++x) {
        if (x < 0 || x >= nx_) continue;
        if (std::max(std::abs(x - cx), std::abs(y - cy)) != ring) continue;
        const int c = cell_index(x, y);
        for (int i = cell_start_[c]; i < cell_start_[c + 1]; ++i) {
          any = true;
          best.offer(cell_faces_[i], raw_weights(cell_faces_[i], point));
        }
      }
    }
    if (best.inside()) break;
    if (any && found_ring < 0) found_ring = ring;
    if (found_ring >= 0 && ring >= found_ring + 2) break;
  }
  return best.result();
}

SphereLocator::SphereLocator(const Positions& points, const Triangles& triangles)
    : points_(points), triangles_(triangles) {
  check_locator_faces(triangles, points.rows(), "SphereLocator");
  if (!points.allFinite()) throw InvalidInput("SphereLocator: a point is not finite");
  // Cells of side h with about one face each on the sphere's 4 pi of area; at most 128 a side.
  const double h = std::sqrt(4 * 3.141592653589793 / static_cast<double>(triangles.rows()));
  n_ = std::clamp(static_cast<int>(std::ceil(2.0 / h)), 1, 128);
  const double cell = 2.0 / n_;
  const auto to_cell = [&](double x) {
    return std::clamp(static_cast<int>(std::floor((x + 1) / cell)), 0, n_ - 1);
  };
  bucket_faces(
      n_ * n_ * n_, triangles.rows(),
      [&](Eigen::Index f, auto&& add) {
        Eigen::Vector3d lo = points.row(triangles(f, 0)).transpose(), hi = lo;
        double longest = 0;
        for (int k = 0; k < 3; ++k) {
          const Eigen::Vector3d p = points.row(triangles(f, k)).transpose();
          lo = lo.cwiseMin(p);
          hi = hi.cwiseMax(p);
          longest =
              std::max(longest, (p - points.row(triangles(f, (k + 1) % 3)).transpose()).norm());
        }
        // The spherical triangle above the chordal one bulges out by at most its circumradius
        // squared over 2 (the sagitta), less than the longest side squared.
        const double bulge = longest * longest + 1e-12;
        lo.array() -= bulge;
        hi.array() += bulge;
        for (int z = to_cell(lo.z()); z <= to_cell(hi.z()); ++z) {
          for (int y = to_cell(lo.y()); y <= to_cell(hi.y()); ++y) {
            for (int x = to_cell(lo.x()); x <= to_cell(hi.x()); ++x) add((z * n_ + y) * n_ + x);
          }
        }
      },
      cell_start_, cell_faces_);
}

Eigen::Vector3d SphereLocator::raw_weights(int face, const Eigen::Vector3d& p) const {
  const Eigen::Vector3d a = points_.row(triangles_(face, 0)).transpose();
  const Eigen::Vector3d ab = points_.row(triangles_(face, 1)).transpose() - a;
  const Eigen::Vector3d ac = points_.row(triangles_(face, 2)).transpose() - a;
  // Everything relative to corner a: a conformal map shrinks faces to 1e-11 of the sphere, where
  // triple products of the corners themselves cancel to noise.
  const Eigen::Vector3d n = ab.cross(ac);
  const double nn = n.squaredNorm();
  const double along = n.dot(p);
  if (!(nn > 0) || !(along > 0)) {
    // Degenerate, or the ray from the origin through p leaves the plane behind it (the face is
    // on the far side of the sphere).
    return Eigen::Vector3d::Constant(along > 0 ? std::numeric_limits<double>::quiet_NaN() : -1e300);
  }
  // Where the ray crosses the face's plane, relative to a: t p - a with t = (n . a) / (n . p),
  // written as p - a + (t - 1) p with t - 1 = n . (a - p) / (n . p).
  const Eigen::Vector3d d = (p - a) + (n.dot(a - p) / along) * p;
  const double beta = d.cross(ac).dot(n) / nn;
  const double gamma = ab.cross(d).dot(n) / nn;
  return {1 - beta - gamma, beta, gamma};
}

FaceLocation SphereLocator::locate(const Eigen::Vector3d& point) const {
  Best best;
  const double norm = point.norm();
  if (!(norm > 0) || !point.allFinite()) return best.result();
  const Eigen::Vector3d p = point / norm;
  const double cell = 2.0 / n_;
  const auto to_cell = [&](double x) {
    return std::clamp(static_cast<int>(std::floor((x + 1) / cell)), 0, n_ - 1);
  };
  const int cx = to_cell(p.x()), cy = to_cell(p.y()), cz = to_cell(p.z());
  int found_ring = -1;
  for (int ring = 0; ring <= n_; ++ring) {
    bool any = false;
    for (int z = std::max(0, cz - ring); z <= std::min(n_ - 1, cz + ring); ++z) {
      for (int y = std::max(0, cy - ring); y <= std::min(n_ - 1, cy + ring); ++y) {
        for (int x = std::max(0, cx - ring); x <= std::min(n_ - 1, cx + ring); ++x) {
          if (std::max({std::abs(x - cx), std::abs(y - cy), std::abs(z - cz)}) != ring) continue;
          const int c = (z * n_ + y) * n_ + x;
          for (int i = cell_start_[c]; i < cell_start_[c + 1]; ++i) {
            any = true;
            best.offer(cell_faces_[i], raw_weights(cell_faces_[i], p));
          }
        }
      }
    }
    if (best.inside()) break;
    if (any && found_ring < 0) found_ring = ring;
    if (found_ring >= 0 && ring >= found_ring + 2) break;
  }
  return best.result();
}

}  // namespace ricci
