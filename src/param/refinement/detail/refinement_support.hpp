#pragma once
/// \file
/// What the steps of common_refinement share (internal): the replayed triangulations and their
/// overlays, the points on the Delaunay edges, the final corners around each vertex, and the
/// pieces that slicing a Delaunay triangle makes (ricci/param/refinement/common_refinement.hpp).

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "ricci/errors.hpp"
#include "ricci/intrinsic/edge_overlay.hpp"
#include "ricci/intrinsic/intrinsic_triangulation.hpp"
#include "ricci/numerics/complex.hpp"
#include "ricci/param/refinement/common_refinement.hpp"

namespace ricci::refinement_support {
using Complex = std::complex<double>;
using Vec3 = Eigen::Vector3d;

[[noreturn]] inline void internal_error(const std::string& what) {
  throw SolverError("common_refinement: " + what);
}

inline double log_sum_exp(double a, double b) {
  const double m = std::max(a, b);
  return m + std::log(std::exp(a - m) + std::exp(b - m));
}

/// Sparse row of weights over input vertices.
using Row = std::vector<std::pair<int, double>>;

inline Row lerp_rows(const Row& a, const Row& b, double t) {
  Row r;
  for (const auto& [v, w] : a) r.push_back({v, (1 - t) * w});
  for (const auto& [v, w] : b) {
    auto it = std::find_if(r.begin(), r.end(), [v = v](const auto& p) { return p.first == v; });
    if (it == r.end()) {
      r.push_back({v, t * w});
    } else {
      it->second += t * w;
    }
  }
  return r;
}

/// A point that lies on a final edge: its parameter from the tail of the edge's halfedge 0 in
/// the final metric, and log w (the factor from the Delaunay triangle's normalisation of its
/// homogeneous coordinates to the final triangle's).
struct FinalEdgePoint {
  int edge = -1;
  double s = 0;
  double log_w = 0;
};

/// Homogeneous barycentric coordinates in a final face, stored as a direction and log w.
struct FinalFacePoint {
  int face = -1;
  Vec3 bary = Vec3::Zero();  ///< sums to 1
  double log_w = 0;
};

/// The point of a final edge at parameter s (from the tail of halfedge 0) in the final face of
/// halfedge h, as barycentric coordinates there.
inline Vec3 bary_on_halfedge(const Topology& tp, int h, double s) {
  const int e = tp.halfedge_edge[h];
  const double sigma = h == tp.edge_halfedges(e, 0) ? s : 1 - s;
  Vec3 b = Vec3::Zero();
  b[(h % 3 + 1) % 3] += 1 - sigma;
  b[(h % 3 + 2) % 3] += sigma;
  return b;
}

/// (w b) of two points combined linearly: weights (1 - t) and t on the homogeneous coordinates.
inline FinalFacePoint homogeneous_lerp(const Vec3& b0, double lw0, const Vec3& b1, double lw1,
                                       double t) {
  const double m = std::max(lw0, lw1);
  const double w0 = (1 - t) * std::exp(lw0 - m), w1 = t * std::exp(lw1 - m);
  FinalFacePoint p;
  p.bary = (w0 * b0 + w1 * b1) / (w0 + w1);
  p.log_w = m + std::log(w0 + w1);
  return p;
}

/// A rigid motion z -> a z + b of the plane.
struct Rigid {
  Complex a{1}, b{0};
  Complex operator()(Complex z) const { return a * z + b; }
};

inline Rigid compose(const Rigid& outer, const Rigid& inner) {
  return {outer.a * inner.a, outer.a * inner.b + outer.b};
}

/// The rigid motion taking segment (p0, p1) onto (q0, q1) (rotation from the directions,
/// midpoints matched).
inline Rigid segment_motion(Complex p0, Complex p1, Complex q0, Complex q1) {
  Complex a = (q1 - q0) / (p1 - p0);
  a /= std::abs(a);
  return {a, 0.5 * (q0 + q1) - a * 0.5 * (p0 + p1)};
}

/// The state common_refinement builds step by step and the slicing of each Delaunay triangle
/// reads: the three triangulations, the overlays, the points on the Delaunay edges.
struct Context {
  const Mesh& mesh;  ///< the surface flowed: the mesh parameterized, or its double
  const Parameterization& param;
  /// T0, T1 and T': the input, and the replays replay_flips_with_overlay returns (read only here:
  /// the intrinsic module writes a flipped triangulation's arrays)
  Topology t0, t1, tp;
  Eigen::VectorXd l0, l1;
  EdgeOverlay o01;  ///< input edges over T1
  EdgeOverlay oT;   ///< final edges over T1
  FaceShapes final_shapes;
  const Eigen::VectorXd& u;
  // Per T1 edge, per entry of o01 / oT: parameter along halfedge 0 and the refinement vertex.
  std::vector<std::vector<double>> a_s, a_tau, b_s;
  std::vector<std::vector<FinalEdgePoint>> b_final;
  std::vector<std::vector<int>> a_vertex, b_vertex;
  /// Per T1 edge, its points in order along halfedge 0: (is a final-edge crossing, entry).
  std::vector<std::vector<std::pair<bool, int>>> ports;
  std::vector<int> segment_offset;  ///< per T1 edge: id of its first segment
  /// Per T1 face, the final edges' arcs in it (face_arcs of oT).
  std::vector<std::vector<FaceArc>> b_arcs;
  /// Per T1 corner 3 t + k: the final corners just counter-clockwise of each final edge leaving
  /// the corner's vertex into t, in counter-clockwise order.
  std::vector<std::vector<std::pair<int, int>>> departures;
  std::vector<std::pair<int, int>> start_wedge_cache;

  // Refinement vertices beyond the input's.
  std::vector<Row> rows;
  std::vector<int> on_input_edge;  ///< input edge the vertex lies on, or -1
  /// 0: an input edge crosses a Delaunay edge there; 1: a Delaunay edge a final edge; 2: an
  /// input edge a final edge, inside a Delaunay triangle
  std::vector<char> kind;
  std::vector<FinalEdgePoint> on_final_edge;
  std::vector<FinalFacePoint> in_final_face;  ///< A-points inside a final face
  int num_edge_ids = 0;

  Context(const Mesh& m, const Parameterization& p, const Eigen::VectorXd& final_u)
      : mesh(m), param(p), u(final_u) {}

  /// Appends a refinement vertex of the given kind; returns its index (after the mesh's
  /// vertices).
  int add_vertex(Row row, int input_edge, char point_kind) {
    rows.push_back(std::move(row));
    on_input_edge.push_back(input_edge);
    kind.push_back(point_kind);
    on_final_edge.push_back({});
    in_final_face.push_back({});
    return mesh.num_vertices() + static_cast<int>(rows.size()) - 1;
  }

  /// The final corner (face, corner) covering the directions just counter-clockwise of the side
  /// from corner k toward corner k + 1 of T1 face t: the wedge of the last final edge met turning
  /// clockwise around the vertex from there.
  std::pair<int, int> start_wedge(int t, int k) {
    auto& cached = start_wedge_cache[3 * t + k];
    if (cached.first >= 0) return cached;
    int face = t, corner = k;
    for (int steps = 0; steps <= 3 * t1.num_faces; ++steps) {
      const int hs = 3 * face + (corner + 2) % 3;
      const int e1 = t1.halfedge_edge[hs];
      if (oT.coincident[e1] != 0) {
        const int ep = std::abs(oT.coincident[e1]) - 1;
        const bool same = (hs == t1.edge_halfedges(e1, 0)) == (oT.coincident[e1] > 0);
        const int hp = same ? tp.edge_halfedges(ep, 0) : tp.edge_halfedges(ep, 1);
        return cached = {hp / 3, (hp % 3 + 1) % 3};
      }
      const int hn = t1.halfedge_twin[hs];
      if (hn < 0) internal_error("a boundary edge of the Delaunay triangulation is no final edge");
      face = hn / 3;
      corner = (hn % 3 + 2) % 3;
      const auto& d = departures[3 * face + corner];
      if (!d.empty()) return cached = d.back();
    }
    internal_error("no final edge leaves vertex " + std::to_string(t1.triangles(t, k)));
  }

  /// The final corner holding the start of T1 halfedge h (not a final edge).
  std::pair<int, int> wedge_of_halfedge(int h) { return start_wedge(h / 3, (h % 3 + 1) % 3); }
};

/// Makes values along a list non-decreasing (and in [0, 1]); returns how many moved.
inline int repair_order(std::vector<double*>& values) {
  int moved = 0;
  double previous = 0;
  for (double* v : values) {
    const double fixed = std::clamp(*v, previous, 1.0);
    if (fixed != *v) {
      *v = fixed;
      ++moved;
    }
    previous = fixed;
  }
  return moved;
}

/// One triangle of the refinement, as the slicing makes it.
struct Piece {
  std::array<int, 3> vertex{};
  int input_face = -1, delaunay_face = -1, final_face = -1;
  std::array<Vec3, 3> delaunay_bary, final_bary;
  std::array<double, 3> log_w{};
  std::array<int, 3> edge_id{};  ///< edge k joins corners k + 1 and k + 2
  std::array<int, 3> input_edge{-1, -1, -1};
  std::array<int, 3> final_halfedge{-1, -1, -1};  ///< final halfedge (of final_face) under edge k
};

/// Cuts Delaunay face t along the input edges and final edges crossing it and appends the
/// cells, fanned into triangles (src/param/refinement/refinement_slicing.cpp).
void slice_delaunay_face(Context& c, int t, std::vector<Piece>& out, CommonRefinement& result);

}  // namespace ricci::refinement_support
