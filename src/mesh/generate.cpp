#include "ricci/mesh/generate.hpp"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/Geometry>

#include "ricci/errors.hpp"

namespace ricci {
namespace {

/// Diagonals of a quad whose squared lengths agree to this relative amount are a tie, broken the
/// same way on every platform (the rounding of the coordinates must not choose).
constexpr double kDiagonalTie = 1e-9;
/// The icosahedron's vertices are exact up to rounding, its squared edge length 4: neighbours
/// are the pairs at that distance to well within any rounding of the coordinates.
constexpr double kIcosahedronEdgeSlack = 1e-9;

using Point = Eigen::Vector3d;

void require_at_least(const char* function, const char* name, long long value, long long least) {
  if (value < least) {
    throw InvalidInput(std::string(function) + ": " + name +
                       " must be >= " + std::to_string(least) + ", got " + std::to_string(value));
  }
}

void require_positive(const char* function, const char* name, double value) {
  if (!std::isfinite(value) || value <= 0.0) {
    throw InvalidInput(std::string(function) + ": " + name + " must be finite and > 0, got " +
                       std::to_string(value));
  }
}

/// Mesh indices are int: refuse sizes whose counts would overflow rather than wrap around.
void require_index_range(const char* function, const char* what, long long count) {
  if (count > INT_MAX) {
    throw InvalidInput(std::string(function) + ": " + what + " = " + std::to_string(count) +
                       " exceeds the int index range");
  }
}

/// Splits the counter-clockwise quad (a, b, c, d) along its shorter diagonal, the one that gives
/// the larger smallest angle for the near-planar quads generated here. Exact ties (flat squares)
/// and near ties go to a-c, so that flat regions get one consistent diagonal whatever the
/// rounding of their coordinates.
void split_quad(const Positions& positions, const std::array<int, 4>& q,
                std::vector<std::array<int, 3>>& triangles) {
  const double ac = (positions.row(q[2]) - positions.row(q[0])).squaredNorm();
  const double bd = (positions.row(q[3]) - positions.row(q[1])).squaredNorm();
  if (bd < ac * (1.0 - kDiagonalTie)) {
    triangles.push_back({q[0], q[1], q[3]});
    triangles.push_back({q[1], q[2], q[3]});
  } else {
    triangles.push_back({q[0], q[1], q[2]});
    triangles.push_back({q[0], q[2], q[3]});
  }
}

Triangles to_triangles(const std::vector<std::array<int, 3>>& list) {
  Triangles t(static_cast<Eigen::Index>(list.size()), 3);
  for (std::size_t f = 0; f < list.size(); ++f) {
    for (int k = 0; k < 3; ++k) t(static_cast<Eigen::Index>(f), k) = list[f][k];
  }
  return t;
}

// ---------------------------------------------------------------------------------------------
// Thickened plates: the closed surfaces of any genus.

/// A plate made of coarse unit cells (columns x rows, some removed to make tunnels), each cell
/// cut into `cell` x `cell` fine pixels, extruded `layers` fine cells thick.
struct Plate {
  int columns = 1;
  int rows = 1;
  std::vector<char> solid;  ///< columns * rows, 1 where the coarse cell is part of the plate
  int cell = 1;             ///< fine pixels along one coarse cell
  int layers = 1;           ///< fine cells across the thickness

  int nx() const { return columns * cell; }
  int ny() const { return rows * cell; }
  /// Whether fine pixel (x, y) is part of the plate; pixels outside the grid are not.
  bool inside(int x, int y) const {
    if (x < 0 || y < 0 || x >= nx() || y >= ny()) return false;
    return solid[(x / cell) + columns * (y / cell)] != 0;
  }
};

/// Coarse layout: genus 0 is a single cube; genus g >= 1 a (2g+1) x 3 plate whose tunnels are the
/// cells (2i+1, 1), one cell apart, so that no two remaining cells touch only at a corner (which
/// would make a non-manifold vertex). The plate is one cell thick, so every arm has a square
/// cross-section. Each coarse cell gets about resolution / columns fine pixels, at least
/// `min_cell`.
Plate make_plate(const char* function, int genus, int resolution, int min_cell) {
  require_at_least(function, "genus", genus, 0);
  require_at_least(function, "resolution", resolution, 1);
  // Past this the face count overflows int whatever the resolution (12 faces per coarse cell).
  require_index_range(function, "12 * 3 * (2 genus + 1)", 36LL * (2LL * genus + 1));
  Plate p;
  if (genus == 0) {
    p.columns = 1;
    p.rows = 1;
    p.solid.assign(1, 1);
  } else {
    p.columns = 2 * genus + 1;
    p.rows = 3;
    p.solid.assign(static_cast<std::size_t>(p.columns) * p.rows, 1);
    for (int i = 0; i < genus; ++i) p.solid[(2 * i + 1) + p.columns] = 0;
  }
  p.cell = std::max(min_cell,
                    static_cast<int>(std::lround(static_cast<double>(resolution) / p.columns)));
  p.layers = p.cell;
  // Rough upper bound on the face count: top, bottom and every side of every coarse cell.
  const long long per_cell = 6LL * p.cell * p.cell * 2;
  require_index_range(function, "face count", per_cell * p.columns * p.rows);
  return p;
}

/// The closed quad surface of a plate, before triangulation.
struct QuadSurface {
  Positions positions;
  std::vector<std::array<int, 4>> quads;  ///< counter-clockwise seen from outside
  std::vector<int> top_quad;              ///< nx * ny: quad on the top of each pixel, or -1
};

QuadSurface build_plate_surface(const Plate& plate) {
  const int nx = plate.nx();
  const int ny = plate.ny();
  const int nz = plate.layers;
  const auto point = [nx](int x, int y) { return x + (nx + 1) * y; };
  const int num_points = (nx + 1) * (ny + 1);

  // A lattice point is on the top (and bottom) when one of its four pixels is inside, and on
  // the rim when it also touches a pixel outside; only rim points get vertices between the
  // top and the bottom layer.
  std::vector<int> top_id(num_points, -1), bottom_id(num_points, -1), rim_id(num_points, -1);
  int count = 0;
  for (int pass = 0; pass < 3; ++pass) {
    for (int y = 0; y <= ny; ++y) {
      for (int x = 0; x <= nx; ++x) {
        const int in = plate.inside(x - 1, y - 1) + plate.inside(x, y - 1) +
                       plate.inside(x - 1, y) + plate.inside(x, y);
        if (in == 0) continue;
        const int p = point(x, y);
        if (pass == 0) {
          top_id[p] = count++;
        } else if (pass == 1) {
          bottom_id[p] = count++;
        } else if (in < 4) {
          rim_id[p] = count;
          count += nz - 1;
        }
      }
    }
  }
  const auto vertex = [&](int x, int y, int z) {
    const int p = point(x, y);
    if (z == nz) return top_id[p];
    if (z == 0) return bottom_id[p];
    return rim_id[p] + z - 1;
  };

  QuadSurface s;
  s.positions.resize(count, 3);
  const double h = 1.0 / plate.cell;  // coarse cells have unit size
  for (int y = 0; y <= ny; ++y) {
    for (int x = 0; x <= nx; ++x) {
      const int p = point(x, y);
      if (top_id[p] < 0) continue;
      const double px = (x - 0.5 * nx) * h;
      const double py = (y - 0.5 * ny) * h;
      for (int z = 0; z <= nz; ++z) {
        if (z != 0 && z != nz && rim_id[p] < 0) continue;
        s.positions.row(vertex(x, y, z)) << px, py, (z - 0.5 * nz) * h;
      }
    }
  }

  s.top_quad.assign(static_cast<std::size_t>(nx) * ny, -1);
  for (int y = 0; y < ny; ++y) {
    for (int x = 0; x < nx; ++x) {
      if (!plate.inside(x, y)) continue;
      s.top_quad[x + nx * y] = static_cast<int>(s.quads.size());
      s.quads.push_back(
          {vertex(x, y, nz), vertex(x + 1, y, nz), vertex(x + 1, y + 1, nz), vertex(x, y + 1, nz)});
      s.quads.push_back(
          {vertex(x, y, 0), vertex(x, y + 1, 0), vertex(x + 1, y + 1, 0), vertex(x + 1, y, 0)});
    }
  }
  // Side walls: one column of nz quads on every pixel edge between inside and outside, facing
  // the outside pixel.
  for (int y = 0; y < ny; ++y) {
    for (int x = 0; x <= nx; ++x) {
      const bool left = plate.inside(x - 1, y);
      if (left == plate.inside(x, y)) continue;
      for (int z = 0; z < nz; ++z) {
        const int a = vertex(x, y, z), b = vertex(x, y + 1, z);
        const int c = vertex(x, y + 1, z + 1), d = vertex(x, y, z + 1);
        if (left) {
          s.quads.push_back({a, b, c, d});  // faces +x
        } else {
          s.quads.push_back({a, d, c, b});  // faces -x
        }
      }
    }
  }
  for (int y = 0; y <= ny; ++y) {
    for (int x = 0; x < nx; ++x) {
      const bool below = plate.inside(x, y - 1);
      if (below == plate.inside(x, y)) continue;
      for (int z = 0; z < nz; ++z) {
        const int a = vertex(x, y, z), b = vertex(x, y, z + 1);
        const int c = vertex(x + 1, y, z + 1), d = vertex(x + 1, y, z);
        if (below) {
          s.quads.push_back({a, b, c, d});  // faces +y
        } else {
          s.quads.push_back({a, d, c, b});  // faces -y
        }
      }
    }
  }
  return s;
}

/// Taubin's lambda|mu smoothing (Taubin 1995, "A signal processing approach to fair surface
/// design") with the uniform Laplacian over quad edges. Flat regions of the lattice are fixed
/// points; sharp edges and corners round off over a few cells while the volume barely shrinks,
/// unlike plain Laplacian smoothing.
void smooth_taubin(Positions& positions, const std::vector<std::array<int, 4>>& quads,
                   int iterations) {
  const int nv = static_cast<int>(positions.rows());
  // Every quad edge a->b appears once in each direction over a closed quad surface, so summing
  // over directed quad edges visits each neighbour exactly once.
  std::vector<int> degree(nv, 0);
  for (const auto& q : quads) {
    for (int k = 0; k < 4; ++k) ++degree[q[k]];
  }
  Positions average(nv, 3);
  const auto step = [&](double factor) {
    average.setZero();
    for (const auto& q : quads) {
      for (int k = 0; k < 4; ++k) average.row(q[k]) += positions.row(q[(k + 1) % 4]);
    }
    for (int v = 0; v < nv; ++v) {
      const Eigen::RowVector3d delta = average.row(v) / degree[v] - positions.row(v);
      positions.row(v) += factor * delta;
    }
  };
  for (int i = 0; i < iterations; ++i) {
    step(0.5);
    step(-0.53);
  }
}

/// Iterations of smooth_taubin: enough to round the edges of the solid over about two cells, few
/// enough to keep every triangle well shaped. Plates of one cube per cell stay unsmoothed: with
/// no cell inside a face, smoothing would shrink the whole solid (a cube to half its size)
/// instead of rounding its edges.
int plate_smoothing(const Plate& plate) {
  return plate.cell > 1 ? 6 : 0;
}

/// Lower-left pixels of the blocks of size x size top pixels that could become holes: each has a
/// ring of inside pixels around it, so that the hole lies inside the top face, and the blocks lie
/// on a lattice with one pixel between neighbours, so that no two holes share a vertex (which
/// would make it non-manifold).
std::vector<std::array<int, 2>> hole_candidates(const Plate& plate, int size) {
  std::vector<std::array<int, 2>> candidates;
  const int stride = size + 1;
  for (int y0 = 1; y0 + size < plate.ny(); y0 += stride) {
    for (int x0 = 1; x0 + size < plate.nx(); x0 += stride) {
      bool ok = true;
      for (int y = y0 - 1; y <= y0 + size && ok; ++y) {
        for (int x = x0 - 1; x <= x0 + size && ok; ++x) ok = plate.inside(x, y);
      }
      if (ok) candidates.push_back({x0, y0});
    }
  }
  return candidates;
}

/// Picks `count` <= candidates.size() candidates spread out by farthest-point sampling, starting
/// from the one nearest to (cx, cy).
std::vector<std::array<int, 2>> spread_out(const std::vector<std::array<int, 2>>& candidates,
                                           int count, double cx, double cy) {
  const auto distance2 = [](const std::array<int, 2>& a, double bx, double by) {
    return (a[0] - bx) * (a[0] - bx) + (a[1] - by) * (a[1] - by);
  };
  std::size_t next = 0;
  for (std::size_t i = 1; i < candidates.size(); ++i) {
    if (distance2(candidates[i], cx, cy) < distance2(candidates[next], cx, cy)) next = i;
  }
  std::vector<double> nearest(candidates.size(), std::numeric_limits<double>::infinity());
  std::vector<std::array<int, 2>> chosen;
  while (static_cast<int>(chosen.size()) < count) {
    chosen.push_back(candidates[next]);
    const auto& c = candidates[next];
    std::size_t farthest = 0;
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      nearest[i] = std::min(nearest[i], distance2(candidates[i], c[0], c[1]));
      if (nearest[i] > nearest[farthest]) farthest = i;
    }
    next = farthest;
  }
  return chosen;
}

/// Triangulates the quads not marked removed and drops the vertices no triangle uses.
Mesh triangulate_quads(const QuadSurface& s, const std::vector<char>& removed) {
  std::vector<std::array<int, 3>> list;
  list.reserve(2 * s.quads.size());
  for (std::size_t q = 0; q < s.quads.size(); ++q) {
    if (!removed.empty() && removed[q]) continue;
    split_quad(s.positions, s.quads[q], list);
  }
  const int nv = static_cast<int>(s.positions.rows());
  std::vector<int> new_index(nv, -1);
  for (const auto& t : list) {
    for (int v : t) new_index[v] = 0;
  }
  int count = 0;
  for (int v = 0; v < nv; ++v) {
    if (new_index[v] == 0) new_index[v] = count++;
  }
  Mesh mesh;
  mesh.positions.resize(count, 3);
  for (int v = 0; v < nv; ++v) {
    if (new_index[v] >= 0) mesh.positions.row(new_index[v]) = s.positions.row(v);
  }
  for (auto& t : list) {
    for (int& v : t) v = new_index[v];
  }
  mesh.triangles = to_triangles(list);
  return mesh;
}

}  // namespace

Mesh make_tetrahedron(double edge_length) {
  require_positive("make_tetrahedron", "edge_length", edge_length);
  // Alternate corners of the cube [-s, s]^3: every edge is a face diagonal of length 2 sqrt(2) s,
  // and every coordinate is +-s, so all six lengths round identically.
  const double s = edge_length / (2.0 * std::numbers::sqrt2);
  Mesh mesh;
  mesh.positions.resize(4, 3);
  mesh.positions << s, s, s, s, -s, -s, -s, s, -s, -s, -s, s;
  mesh.triangles.resize(4, 3);
  mesh.triangles << 1, 3, 2, 0, 2, 3, 0, 3, 1, 0, 1, 2;
  return mesh;
}

Mesh make_icosphere(int subdivisions, double radius) {
  require_at_least("make_icosphere", "subdivisions", subdivisions, 0);
  require_positive("make_icosphere", "radius", radius);
  if (subdivisions > 12) {
    throw InvalidInput("make_icosphere: subdivisions must be <= 12 (20 * 4^s faces), got " +
                       std::to_string(subdivisions));
  }
  // Icosahedron: the cyclic permutations of (0, +-1, +-phi). Its faces are the triples of
  // mutually adjacent vertices (at distance 2), oriented so that their normal points away from
  // the centre.
  const double phi = std::numbers::phi;
  std::vector<Point> points;
  for (int axis = 0; axis < 3; ++axis) {
    for (double a : {-1.0, 1.0}) {
      for (double b : {-phi, phi}) {
        Point p = Point::Zero();
        p[(axis + 1) % 3] = a;
        p[(axis + 2) % 3] = b;
        points.push_back(p);
      }
    }
  }
  const auto adjacent = [&](int i, int j) {
    return std::abs((points[i] - points[j]).squaredNorm() - 4.0) < kIcosahedronEdgeSlack;
  };
  std::vector<std::array<int, 3>> faces;
  for (int i = 0; i < 12; ++i) {
    for (int j = i + 1; j < 12; ++j) {
      for (int k = j + 1; k < 12; ++k) {
        if (!adjacent(i, j) || !adjacent(j, k) || !adjacent(i, k)) continue;
        const Point n = (points[j] - points[i]).cross(points[k] - points[i]);
        if (n.dot(points[i]) > 0) {
          faces.push_back({i, j, k});
        } else {
          faces.push_back({i, k, j});
        }
      }
    }
  }
  for (auto& p : points) p.normalize();

  for (int level = 0; level < subdivisions; ++level) {
    std::unordered_map<std::uint64_t, int> midpoint;
    midpoint.reserve(faces.size() * 3 / 2);
    const auto split = [&](int a, int b) {
      const std::uint64_t key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) |
                                static_cast<std::uint64_t>(std::max(a, b));
      const auto [it, inserted] = midpoint.try_emplace(key, static_cast<int>(points.size()));
      if (inserted) points.push_back((points[a] + points[b]).normalized());
      return it->second;
    };
    std::vector<std::array<int, 3>> finer;
    finer.reserve(4 * faces.size());
    for (const auto& [a, b, c] : faces) {
      const int ab = split(a, b), bc = split(b, c), ca = split(c, a);
      finer.push_back({a, ab, ca});
      finer.push_back({b, bc, ab});
      finer.push_back({c, ca, bc});
      finer.push_back({ab, bc, ca});
    }
    faces = std::move(finer);
  }

  Mesh mesh;
  mesh.positions.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t v = 0; v < points.size(); ++v) {
    mesh.positions.row(static_cast<Eigen::Index>(v)) = radius * points[v].normalized();
  }
  mesh.triangles = to_triangles(faces);
  return mesh;
}

Mesh make_disk(int rings, double bulge) {
  require_at_least("make_disk", "rings", rings, 1);
  if (!std::isfinite(bulge)) {
    throw InvalidInput("make_disk: bulge must be finite, got " + std::to_string(bulge));
  }
  require_index_range("make_disk", "face count", 6LL * rings * rings);
  const int nv = 1 + 3 * rings * (rings + 1);
  Mesh mesh;
  mesh.positions.resize(nv, 3);
  mesh.positions.row(0) << 0.0, 0.0, bulge;
  // Ring r (radius r / rings) holds 6 r vertices evenly spaced in angle, starting at angle 0;
  // its first vertex has index 1 + 3 r (r - 1).
  const auto first = [](int r) { return 1 + 3 * r * (r - 1); };
  for (int r = 1; r <= rings; ++r) {
    const double radius = static_cast<double>(r) / rings;
    for (int k = 0; k < 6 * r; ++k) {
      const double angle = 2.0 * std::numbers::pi * k / (6 * r);
      const double x = radius * std::cos(angle), y = radius * std::sin(angle);
      mesh.positions.row(first(r) + k) << x, y, bulge * (1.0 - radius * radius);
    }
  }
  mesh.triangles.resize(6LL * rings * rings, 3);
  int f = 0;
  for (int k = 0; k < 6; ++k) mesh.triangles.row(f++) << 0, first(1) + k, first(1) + (k + 1) % 6;
  // Between rings r-1 and r, the triangles of the hexagonal lattice: in each of the six sectors
  // the inner ring has r-1 vertices (plus the next sector's corner) and the outer ring r, and
  // the strip alternates triangles with an outer edge and triangles with an inner edge, so that
  // every interior vertex has degree 6.
  for (int r = 2; r <= rings; ++r) {
    const int n_in = 6 * (r - 1), n_out = 6 * r;
    const auto inner = [&](int i) { return first(r - 1) + i % n_in; };
    const auto outer = [&](int i) { return first(r) + i % n_out; };
    for (int sector = 0; sector < 6; ++sector) {
      for (int i = 0; i < r; ++i) {
        const int a = sector * (r - 1) + i, b = sector * r + i;
        mesh.triangles.row(f++) << inner(a), outer(b), outer(b + 1);
        if (i + 1 < r) mesh.triangles.row(f++) << inner(a), outer(b + 1), inner(a + 1);
      }
    }
  }
  return mesh;
}

Mesh make_torus(int major_segments, int minor_segments, double major_radius, double minor_radius) {
  require_at_least("make_torus", "major_segments", major_segments, 3);
  require_at_least("make_torus", "minor_segments", minor_segments, 3);
  require_positive("make_torus", "major_radius", major_radius);
  require_positive("make_torus", "minor_radius", minor_radius);
  if (minor_radius >= major_radius) {
    throw InvalidInput("make_torus: minor_radius must be < major_radius = " +
                       std::to_string(major_radius) + ", got " + std::to_string(minor_radius));
  }
  require_index_range("make_torus", "2 * major_segments * minor_segments",
                      2LL * major_segments * minor_segments);
  const int m = major_segments, n = minor_segments;
  std::vector<double> cos_major(m), sin_major(m), cos_minor(n), sin_minor(n);
  for (int i = 0; i < m; ++i) {
    cos_major[i] = std::cos(2.0 * std::numbers::pi * i / m);
    sin_major[i] = std::sin(2.0 * std::numbers::pi * i / m);
  }
  for (int j = 0; j < n; ++j) {
    cos_minor[j] = std::cos(2.0 * std::numbers::pi * j / n);
    sin_minor[j] = std::sin(2.0 * std::numbers::pi * j / n);
  }
  Mesh mesh;
  mesh.positions.resize(static_cast<Eigen::Index>(m) * n, 3);
  for (int i = 0; i < m; ++i) {
    for (int j = 0; j < n; ++j) {
      const int v = i * n + j;
      const double ring = major_radius + minor_radius * cos_minor[j];
      mesh.positions(v, 0) = ring * cos_major[i];
      mesh.positions(v, 1) = ring * sin_major[i];
      mesh.positions(v, 2) = minor_radius * sin_minor[j];
    }
  }
  // d/d(major angle) x d/d(minor angle) points outwards, so (i, j), (i+1, j), (i+1, j+1) is
  // counter-clockwise from outside. One diagonal direction everywhere gives every vertex degree
  // 6; the grid cells are near-rectangles, for which either diagonal gives the same angles.
  mesh.triangles.resize(2LL * m * n, 3);
  for (int i = 0; i < m; ++i) {
    const int i1 = (i + 1) % m;
    for (int j = 0; j < n; ++j) {
      const int j1 = (j + 1) % n;
      const int a = i * n + j, b = i1 * n + j, c = i1 * n + j1, d = i * n + j1;
      const int f = 2 * a;
      mesh.triangles(f, 0) = a;
      mesh.triangles(f, 1) = b;
      mesh.triangles(f, 2) = c;
      mesh.triangles(f + 1, 0) = a;
      mesh.triangles(f + 1, 1) = c;
      mesh.triangles(f + 1, 2) = d;
    }
  }
  return mesh;
}

Mesh make_grid(int nx, int ny, double width, double height) {
  require_at_least("make_grid", "nx", nx, 1);
  require_at_least("make_grid", "ny", ny, 1);
  require_positive("make_grid", "width", width);
  require_positive("make_grid", "height", height);
  require_index_range("make_grid", "2 * nx * ny", 2LL * nx * ny);
  require_index_range("make_grid", "(nx + 1) * (ny + 1)", (nx + 1LL) * (ny + 1LL));
  Mesh mesh;
  mesh.positions.resize(static_cast<Eigen::Index>(nx + 1) * (ny + 1), 3);
  for (int y = 0; y <= ny; ++y) {
    for (int x = 0; x <= nx; ++x) {
      mesh.positions.row(x + (nx + 1) * y) << width * x / nx, height * y / ny, 0.0;
    }
  }
  mesh.triangles.resize(2LL * nx * ny, 3);
  int f = 0;
  for (int y = 0; y < ny; ++y) {
    for (int x = 0; x < nx; ++x) {
      const int a = x + (nx + 1) * y, b = a + 1, c = b + nx + 1, d = a + nx + 1;
      mesh.triangles.row(f++) << a, b, c;
      mesh.triangles.row(f++) << a, c, d;
    }
  }
  return mesh;
}

Mesh make_closed_surface(int genus, int resolution) {
  const Plate plate = make_plate("make_closed_surface", genus, resolution, 1);
  QuadSurface s = build_plate_surface(plate);
  smooth_taubin(s.positions, s.quads, plate_smoothing(plate));
  return triangulate_quads(s, {});
}

Mesh make_surface_with_holes(int genus, int holes, int resolution) {
  require_at_least("make_surface_with_holes", "holes", holes, 0);
  // Three pixels per coarse cell leave room for a one-pixel hole inside a ring of top pixels.
  const Plate plate = make_plate("make_surface_with_holes", genus, resolution, holes > 0 ? 3 : 1);
  QuadSurface s = build_plate_surface(plate);
  smooth_taubin(s.positions, s.quads, plate_smoothing(plate));
  if (holes == 0) return triangulate_quads(s, {});

  // Holes a third of a coarse cell wide, smaller when that leaves no room for all of them.
  int size = std::max(1, plate.cell / 3);
  std::vector<std::array<int, 2>> candidates = hole_candidates(plate, size);
  while (static_cast<int>(candidates.size()) < holes && size > 1) {
    candidates = hole_candidates(plate, --size);
  }
  if (static_cast<int>(candidates.size()) < holes) {
    throw InvalidInput("make_surface_with_holes: resolution " + std::to_string(resolution) +
                       " leaves room for " + std::to_string(candidates.size()) +
                       " holes on genus " + std::to_string(genus) +
                       ", got holes = " + std::to_string(holes) + "; raise the resolution");
  }
  const auto corners =
      spread_out(candidates, holes, 0.5 * (plate.nx() - size), 0.5 * (plate.ny() - size));
  std::vector<char> removed(s.quads.size(), 0);
  for (const auto& [x0, y0] : corners) {
    for (int y = y0; y < y0 + size; ++y) {
      for (int x = x0; x < x0 + size; ++x) removed[s.top_quad[x + plate.nx() * y]] = 1;
    }
  }
  return triangulate_quads(s, removed);
}

}  // namespace ricci
