#include "param/atlas/detail/unfolding.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <numeric>

#include <Eigen/Geometry>

#include "param/atlas/detail/triangle_grid.hpp"
#include "ricci/metric/angles.hpp"
#include "ricci/metric/curvature.hpp"
#include "ricci/metric/lengths.hpp"
#include "ricci/numerics/disjoint_sets.hpp"
#include "ricci/param/layout/polygon_fans.hpp"

namespace ricci::param_detail {
namespace {

/// An interior vertex whose 3D angle sum is within this of 2 pi is flat, not a cone, in an
/// unfolded component: angle sums inside planar regions round to a few 1e-15.
constexpr double kFlatCurvature = 1e-9;
/// A face developed next to an already developed one lands within rounding of where that one
/// put their shared vertex when the vertex between them is flat: closer than this (relative to
/// the face's longest edge) it takes that position exactly and the two faces are glued.
constexpr double kSnap = 1e-9;
/// The grid cell of embedded_pieces never goes below this (layout units), so that dividing by it
/// stays finite however small the faces (the smallest normal double is 2e-308).
constexpr double kMinCell = 1e-300;

/// A face laid out across the edge of a face already placed: its corners, and the corners it is
/// glued to (across that edge, and across its other edges where it snapped).
struct FacePlacement {
  int face = -1;
  int apex = 0;                                                     ///< the corner laid out
  std::array<std::array<int, 2>, 2> glue{{{-1, -1}, {-1, -1}}};     ///< own corner, other's
  std::array<std::array<int, 2>, 2> snapped{{{-1, -1}, {-1, -1}}};  ///< other's apex, shared
};

/// The state of develop_patches: corner positions, the union-find of glued corners, the grid of
/// the current patch's faces and its frontier, the faces of the polygon joining.
class PatchDevelopment {
 public:
  PatchDevelopment(const Mesh& mesh, const Topology& t, const Polygons& polygons, PatchLayout& out)
      : mesh_(mesh),
        t_(t),
        polygons_(polygons),
        out_(out),
        corner_(3 * t.num_faces),
        glued_(3 * t.num_faces),
        grid_(2 * total_edge_length(mesh, t) / std::max(1, t.num_edges)),
        placing_(t.num_faces, -1) {}

  /// Grows a new patch from `seed` breadth first: a face (with its polygon) joins across an edge
  /// of the patch unless it overlaps a face of the patch (it may still join from another side,
  /// or seed a patch of its own).
  void grow_patch(int seed) {
    const int patch = out_.num_patches++;
    grid_.clear();
    corner_[3 * seed] = Eigen::Vector2d::Zero();
    corner_[3 * seed + 1] = Eigen::Vector2d((position(seed, 1) - position(seed, 0)).norm(), 0);
    corner_[3 * seed + 2] = apex(seed, 2, corner_[3 * seed], corner_[3 * seed + 1]);
    placements_.assign(1, FacePlacement{});
    placements_[0].face = seed;
    placing_[seed] = patch;
    place_polygon(patch);
    join(patch);
    while (!frontier_.empty()) {
      const int h = frontier_.front();
      frontier_.pop_front();
      const int g = Topology::face_of(t_.halfedge_twin[h]);
      if (out_.face_patch[g] >= 0) continue;
      placements_.clear();
      place(h, patch);
      place_polygon(patch);
      bool overlaps = false;
      for (const FacePlacement& placement : placements_) {
        overlaps = overlaps ||
                   grid_.overlaps(triangle(placement.face), [this](int f) { return triangle(f); });
      }
      if (overlaps) {
        for (const FacePlacement& placement : placements_) placing_[placement.face] = -1;
        continue;
      }
      join(patch);
    }
  }

  /// The cut-mesh vertices: one per class of glued corners, numbered in order of first corner,
  /// at the position of the class's smallest corner.
  void number_vertices() {
    const int nf = t_.num_faces;
    std::vector<int> id(3 * nf, -1);
    out_.triangles.resize(nf, 3);
    std::vector<Eigen::Vector2d> positions;
    for (int c = 0; c < 3 * nf; ++c) {
      int& v = id[glued_.find(c)];
      if (v < 0) {
        v = static_cast<int>(out_.vertex.size());
        out_.vertex.push_back(t_.triangles(c / 3, c % 3));
        positions.push_back(corner_[glued_.find(c)]);
      }
      out_.triangles(c / 3, c % 3) = v;
    }
    out_.layout.resize(static_cast<Eigen::Index>(positions.size()), 2);
    for (std::size_t v = 0; v < positions.size(); ++v) {
      out_.layout.row(static_cast<Eigen::Index>(v)) = positions[v].transpose();
    }
  }

 private:
  /// The sum of the 3D edge lengths: the grid's cells are twice their mean.
  static double total_edge_length(const Mesh& mesh, const Topology& t) {
    double mean_length = 0;
    for (int e = 0; e < t.num_edges; ++e) {
      mean_length +=
          (mesh.positions.row(t.edge_vertices(e, 0)) - mesh.positions.row(t.edge_vertices(e, 1)))
              .norm();
    }
    return mean_length;
  }

  Eigen::Vector3d position(int f, int k) const {
    return mesh_.positions.row(t_.triangles(f, k % 3)).transpose();
  }

  /// Where the corner k of face f goes, given where corners k + 1 and k + 2 went: its offset
  /// from corner k + 1 along and across that edge, taken from the 3D triangle (no angle formula,
  /// so a needle face cannot produce NaN).
  Eigen::Vector2d apex(int f, int k, const Eigen::Vector2d& from, const Eigen::Vector2d& to) const {
    const Eigen::Vector3d e = position(f, k + 2) - position(f, k + 1);
    const Eigen::Vector3d d = position(f, k) - position(f, k + 1);
    const double l = e.norm();
    const Eigen::Vector2d u = (to - from).normalized();
    return Eigen::Vector2d(from + d.dot(e) / l * u +
                           e.cross(d).norm() / l * Eigen::Vector2d(-u.y(), u.x()));
  }

  PlanarTriangle triangle(int f) const {
    return PlanarTriangle{corner_[3 * f], corner_[3 * f + 1], corner_[3 * f + 2]};
  }

  /// Across a polygon's diagonals (its triangles' shared edges) its faces always stay together.
  bool same_polygon(int h) const {
    const int twin = t_.halfedge_twin[h];
    return !polygons_.empty() && twin >= 0 &&
           polygons_.triangle_polygon[Topology::face_of(h)] ==
               polygons_.triangle_polygon[Topology::face_of(twin)];
  }

  /// Face f joins the grid, and its edges towards faces of no patch the frontier.
  void add(int f) {
    grid_.insert(f, triangle(f));
    for (int k = 0; k < 3; ++k) {
      const int twin = t_.halfedge_twin[3 * f + k];
      if (twin >= 0 && out_.face_patch[Topology::face_of(twin)] < 0) frontier_.push_back(3 * f + k);
    }
  }

  /// Lays out the face across halfedge h (of a face already placed) for `patch`.
  void place(int h, int patch) {
    // h runs from p to q in its face f; the twin runs from q to p in g, whose corner kg (the
    // apex) lies on its left.
    const int twin = t_.halfedge_twin[h];
    const int g = Topology::face_of(twin);
    const int f = Topology::face_of(h), kf = h % 3, kg = twin % 3;
    const int cp = 3 * f + (kf + 1) % 3, cq = 3 * f + (kf + 2) % 3;
    PlanarTriangle shape;
    shape[kg] = apex(g, kg, corner_[cq], corner_[cp]);
    shape[(kg + 1) % 3] = corner_[cq];
    shape[(kg + 2) % 3] = corner_[cp];
    FacePlacement placement;
    placement.face = g;
    placement.apex = kg;
    placement.glue[0] = {3 * g + (kg + 1) % 3, cq};
    placement.glue[1] = {3 * g + (kg + 2) % 3, cp};
    // Across g's other two edges: a face of the patch that already holds the shared end at
    // exactly this position and the apex within rounding (the vertex between them is flat)
    // gives the apex its position, and g is glued to it too.
    const double snap = kSnap * (corner_[cq] - corner_[cp]).norm();
    for (int side = 1; side <= 2; ++side) {
      const int other = t_.halfedge_twin[3 * g + (kg + side) % 3];
      if (other < 0) continue;
      const int g2 = Topology::face_of(other), k2 = other % 3;
      if (out_.face_patch[g2] != patch) continue;
      // side 1: the edge from p (corner kg + 2) to the apex, whose twin runs apex -> p;
      // side 2: the edge from the apex to q (corner kg + 1), whose twin runs q -> apex.
      const int shared = side == 1 ? (kg + 2) % 3 : (kg + 1) % 3;
      const int c_apex = 3 * g2 + (side == 1 ? (k2 + 1) % 3 : (k2 + 2) % 3);
      const int c_shared = 3 * g2 + (side == 1 ? (k2 + 2) % 3 : (k2 + 1) % 3);
      if (corner_[c_shared] != shape[shared]) continue;
      if ((corner_[c_apex] - shape[kg]).norm() > snap) continue;
      shape[kg] = corner_[c_apex];
      placement.snapped[side - 1] = {c_apex, c_shared};
    }
    for (int k = 0; k < 3; ++k) corner_[3 * g + k] = shape[k];
    placing_[g] = patch;
    placements_.push_back(placement);
  }

  /// The rest of the polygon of the first placement, across its diagonals.
  void place_polygon(int patch) {
    for (std::size_t i = 0; i < placements_.size(); ++i) {
      const int f = placements_[i].face;
      for (int k = 0; k < 3; ++k) {
        const int twin = t_.halfedge_twin[3 * f + k];
        if (!same_polygon(3 * f + k) || placing_[Topology::face_of(twin)] == patch) continue;
        place(3 * f + k, patch);
      }
    }
  }

  /// The placed faces join `patch`: their corners glued, then the faces added to the grid.
  void join(int patch) {
    for (const FacePlacement& placement : placements_) {
      const int g = placement.face, kg = placement.apex;
      out_.face_patch[g] = patch;
      for (const auto& [own, other] : placement.glue) {
        if (own >= 0) glued_.unite(own, other);
      }
      for (int side = 1; side <= 2; ++side) {
        const auto& [c_apex, c_shared] = placement.snapped[side - 1];
        if (c_apex < 0) continue;
        // A snapped apex keeps its position only if the shared end also matched.
        if (corner_[3 * g + kg] != corner_[c_apex]) continue;
        glued_.unite(3 * g + kg, c_apex);
        glued_.unite(3 * g + (side == 1 ? (kg + 2) % 3 : (kg + 1) % 3), c_shared);
      }
    }
    for (const FacePlacement& placement : placements_) add(placement.face);
  }

  const Mesh& mesh_;
  const Topology& t_;
  const Polygons& polygons_;
  PatchLayout& out_;
  std::vector<Eigen::Vector2d> corner_;    ///< position of corner 3 f + k
  DisjointSets glued_;                     ///< corners glued together
  TriangleGrid grid_;                      ///< the faces of the current patch
  std::deque<int> frontier_;               ///< halfedges of patch faces whose other face may join
  std::vector<FacePlacement> placements_;  ///< the faces of the polygon joining
  std::vector<int> placing_;               ///< the patch a face is being placed into
};

}  // namespace

void fit_unit_square(ParamResult& r) {
  const Eigen::Vector2d lo = r.layout.uv.colwise().minCoeff().transpose();
  const Eigen::Vector2d hi = r.layout.uv.colwise().maxCoeff().transpose();
  const double extent = (hi - lo).maxCoeff();
  r.uv_offset = lo;
  r.uv_scale = extent > 0 ? 1.0 / extent : 1.0;
  r.uv = (r.layout.uv.rowwise() - lo.transpose()) * r.uv_scale;
}

PatchLayout develop_patches(const Mesh& mesh, const Polygons& polygons) {
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  PatchLayout out;
  out.face_patch.assign(t.num_faces, -1);
  PatchDevelopment development(mesh, t, polygons, out);
  for (int seed = 0; seed < t.num_faces; ++seed) {
    if (out.face_patch[seed] < 0) development.grow_patch(seed);
  }
  development.number_vertices();
  out.is_glued_edge = glued_edges(t, out.triangles);
  return out;
}

ParamResult unfolded_result(const Mesh& mesh, const PatchLayout& patches,
                            const Polygons& polygons) {
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  const Eigen::VectorXd lengths = input_edge_lengths(mesh, t);
  ParamResult r = own_layout_result(mesh, t, lengths, patches.triangles, patches.vertex,
                                    patches.layout, polygons);
  CornerAngles angles;
  corner_angles(t, lengths, angles);  // a needle face's NaN angles only hide a cone
  const Eigen::VectorXd curvature = vertex_curvature(t, angles);
  for (int v = 0; v < t.num_vertices; ++v) {
    if (t.vertex_component[v] < 0 || t.is_boundary_vertex[v]) continue;
    if (std::abs(curvature[v]) > kFlatCurvature) r.cones.push_back({v, curvature[v]});
  }
  return r;
}

std::vector<char> glued_edges(const Topology& t, const Triangles& cut_triangles) {
  std::vector<char> glued(t.num_edges, 0);
  for (int e = 0; e < t.num_edges; ++e) {
    const int h0 = t.edge_halfedges(e, 0), h1 = t.edge_halfedges(e, 1);
    if (h0 < 0 || h1 < 0) continue;
    // The cut-mesh vertex at the tail (or head) of halfedge h, in its face.
    auto copy = [&](int h, bool tail) {
      return cut_triangles(Topology::face_of(h), (h % 3 + (tail ? 1 : 2)) % 3);
    };
    glued[e] = copy(h0, true) == copy(h1, false) && copy(h0, false) == copy(h1, true);
  }
  return glued;
}

ParamResult own_layout_result(const Mesh& mesh, const Topology& t, const Eigen::VectorXd& lengths,
                              const Triangles& triangles, const std::vector<int>& vertex,
                              const Points& layout, const Polygons& polygons) {
  ParamResult r;
  r.converged = true;
  r.mesh = mesh;
  r.vertex_origin.resize(mesh.num_vertices());
  std::iota(r.vertex_origin.begin(), r.vertex_origin.end(), 0);
  const std::vector<char> glued = glued_edges(t, triangles);
  r.cut.is_cut_edge.assign(t.num_edges, 0);
  for (int e = 0; e < t.num_edges; ++e) {
    if (t.is_boundary_edge[e] || glued[e]) continue;
    r.cut.is_cut_edge[e] = 1;
    r.cut.length += lengths[e];
  }
  r.seam_length = r.cut.length;
  r.cut_mesh.triangles = triangles;
  r.cut_mesh.to_original = vertex;
  r.cut_mesh.topology = build_topology(triangles, static_cast<int>(vertex.size()));
  r.layout.uv = layout;
  r.polygons = start_fans_where_valid(polygons, mesh, r.cut_mesh.triangles, r.layout.uv);
  r.distortion = measure_polygon_distortion(mesh, r.polygons, r.cut_mesh.triangles, r.layout.uv);
  r.layout.num_flipped_faces = r.distortion.flipped_faces;
  fit_unit_square(r);
  return r;
}

std::vector<int> embedded_pieces(const Points& uv, const Triangles& triangles, int& count,
                                 const std::vector<int>& triangle_polygon) {
  const int nf = static_cast<int>(triangles.rows());
  const Topology t = build_topology(triangles, static_cast<int>(uv.rows()));
  std::vector<int> piece(nf, -1);
  auto triangle = [&](int f) {
    std::array<Eigen::Vector2d, 3> out;
    for (int k = 0; k < 3; ++k) out[k] = uv.row(triangles(f, k)).transpose();
    return out;
  };
  // The triangles of each polygon (compressed rows), or each triangle on its own.
  std::vector<int> member_start(nf + 1, 0), members(nf);
  if (triangle_polygon.empty()) {
    std::iota(member_start.begin(), member_start.end(), 0);
    std::iota(members.begin(), members.end(), 0);
  } else {
    for (int f = 0; f < nf; ++f) ++member_start[triangle_polygon[f] + 1];
    for (int p = 0; p < nf; ++p) member_start[p + 1] += member_start[p];
    std::vector<int> fill(member_start.begin(), member_start.end() - 1);
    for (int f = 0; f < nf; ++f) members[fill[triangle_polygon[f]]++] = f;
  }
  auto polygon_of = [&](int f) { return triangle_polygon.empty() ? f : triangle_polygon[f]; };
  double mean = 0;
  for (int f = 0; f < nf; ++f) {
    const auto p = triangle(f);
    mean += (p[0].cwiseMax(p[1]).cwiseMax(p[2]) - p[0].cwiseMin(p[1]).cwiseMin(p[2])).maxCoeff();
  }
  TriangleGrid grid(std::max(2 * mean / std::max(1, nf), kMinCell));
  std::deque<int> frontier;
  count = 0;
  for (int seed = 0; seed < nf; ++seed) {
    if (piece[seed] >= 0) continue;
    grid.clear();
    frontier.assign(1, seed);
    while (!frontier.empty()) {
      const int f = frontier.front();
      frontier.pop_front();
      if (piece[f] >= 0) continue;
      const int p = polygon_of(f);
      bool overlaps = false;
      for (int i = member_start[p]; i < member_start[p + 1] && !overlaps; ++i) {
        overlaps = grid.overlaps(triangle(members[i]), triangle);
      }
      // f may still join from another side, or seed a piece
      if (overlaps) continue;
      for (int i = member_start[p]; i < member_start[p + 1]; ++i) piece[members[i]] = count;
      for (int i = member_start[p]; i < member_start[p + 1]; ++i) {
        const int g = members[i];
        grid.insert(g, triangle(g));
        for (int k = 0; k < 3; ++k) {
          const int twin = t.halfedge_twin[3 * g + k];
          if (twin >= 0 && piece[Topology::face_of(twin)] < 0) {
            frontier.push_back(Topology::face_of(twin));
          }
        }
      }
    }
    ++count;
  }
  return piece;
}

std::vector<int> split_at_charts(Triangles& triangles, int num_layout_vertices,
                                 const std::vector<int>& face_chart) {
  const Topology t = build_topology(triangles, num_layout_vertices);
  DisjointSets corners(3 * t.num_faces);
  for (int h = 0; h < 3 * t.num_faces; ++h) {
    const int twin = t.halfedge_twin[h];
    if (twin < h || face_chart[h / 3] != face_chart[twin / 3]) continue;
    // h runs tail -> head in its face, the twin head -> tail: corner k + 1 is the tail.
    for (const auto& [a, b] :
         {std::pair{3 * (h / 3) + (h % 3 + 1) % 3, 3 * (twin / 3) + (twin % 3 + 2) % 3},
          std::pair{3 * (h / 3) + (h % 3 + 2) % 3, 3 * (twin / 3) + (twin % 3 + 1) % 3}}) {
      corners.unite(a, b);
    }
  }
  std::vector<int> id(3 * t.num_faces, -1);
  std::vector<int> source;
  for (int corner = 0; corner < 3 * t.num_faces; ++corner) {
    const int f = corner / 3, k = corner % 3;
    int& copy = id[corners.find(corner)];
    if (copy < 0) {
      copy = static_cast<int>(source.size());
      source.push_back(triangles(f, k));
    }
    triangles(f, k) = copy;
  }
  return source;
}

}  // namespace ricci::param_detail
