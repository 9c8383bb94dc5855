#include "ricci/spline/powell_sabin.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <string>

#include <Eigen/LU>

#include "ricci/errors.hpp"

namespace ricci {
namespace {

using Vec2 = Eigen::Vector2d;
using Complex = std::complex<double>;

/// The floor of a jump scale that is 0 (constant data): the relative jumps stay finite.
constexpr double kTinyScale = 1e-300;

constexpr int kA = 0, kC = 3, kD = 6, kE = 9, kBP = 12, kBQ = 15, kF = 18;

Complex to_complex(const Vec2& v) {
  return {v.x(), v.y()};
}
Vec2 to_vec(Complex z) {
  return {z.real(), z.imag()};
}
double cross(const Vec2& a, const Vec2& b) {
  return a.x() * b.y() - a.y() * b.x();
}

Vec2 corner(const SplineDomain& d, int f, int k) {
  return {d.corner_uv(f, 2 * k), d.corner_uv(f, 2 * k + 1)};
}

Vec2 split_on_side(const SplineDomain& d, int f, int k) {
  const double lam = d.edge_split(f, k);
  return lam * corner(d, f, (k + 1) % 3) + (1 - lam) * corner(d, f, (k + 2) % 3);
}

/// Rows of the inverse of [P1 - P0, P2 - P0]: gradients of the barycentric coordinates 1 and 2;
/// row 0 is minus their sum. 3 by 2.
Eigen::Matrix<double, 3, 2> barycentric_gradients(const std::array<Vec2, 3>& p) {
  Eigen::Matrix2d m;
  m.col(0) = p[1] - p[0];
  m.col(1) = p[2] - p[0];
  const Eigen::Matrix2d inv = m.inverse();
  Eigen::Matrix<double, 3, 2> j;
  j.row(1) = inv.row(0);
  j.row(2) = inv.row(1);
  j.row(0) = -(j.row(1) + j.row(2));
  return j;
}

Eigen::Vector3d barycentric_in(const std::array<Vec2, 3>& p, const Vec2& x) {
  Eigen::Matrix2d m;
  m.col(0) = p[1] - p[0];
  m.col(1) = p[2] - p[0];
  const Vec2 l = m.inverse() * (x - p[0]);
  return {1 - l.x() - l.y(), l.x(), l.y()};
}

}  // namespace

std::array<int, 6> piece_slots(int piece) {
  const int k = piece / 2;
  if (piece % 2 == 0) {
    return {kA + (k + 1) % 3, kD + k, kF, kBP + k, kC + (k + 1) % 3, kE + k};
  }
  return {kD + k, kA + (k + 2) % 3, kF, kBQ + k, kE + k, kC + (k + 2) % 3};
}

std::array<Vec2, 3> piece_triangle(const SplineDomain& d, int f, int piece) {
  const int k = piece / 2;
  const Vec2 z = d.split_point.row(f).transpose();
  const Vec2 r = split_on_side(d, f, k);
  if (piece % 2 == 0) return {corner(d, f, (k + 1) % 3), r, z};
  return {r, corner(d, f, (k + 2) % 3), z};
}

SplineDomain spline_domain(const Topology& topology, const Triangles& chart_triangles,
                           const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv,
                           const std::vector<int>& fixed_gradient_vertices) {
  const int nf = topology.num_faces;
  const int nv = topology.num_vertices;
  if (chart_triangles.rows() != nf) {
    throw InvalidInput("spline_domain: " + std::to_string(chart_triangles.rows()) +
                       " chart triangles for " + std::to_string(nf) + " faces");
  }
  SplineDomain d;
  d.num_vertices = nv;
  d.num_edges = topology.num_edges;
  d.triangles = topology.triangles;
  d.halfedge_twin = topology.halfedge_twin;
  d.halfedge_edge = topology.halfedge_edge;
  d.corner_uv.resize(nf, 6);
  d.split_point.resize(nf, 2);
  d.split_weights.resize(nf, 3);
  d.edge_split.setConstant(nf, 3, 0.5);
  d.corner_frame.assign(3 * nf, Complex(1));
  d.halfedge_rotation.assign(3 * nf, Complex(1));
  d.halfedge_translation.assign(3 * nf, Complex(0));
  d.fixed_gradient.assign(nv, 0);
  d.referenced.assign(nv, 0);
  for (int v : fixed_gradient_vertices) {
    if (v < 0 || v >= nv) {
      throw InvalidInput("spline_domain: fixed-gradient vertex " + std::to_string(v) +
                         " out of range [0, " + std::to_string(nv) + ")");
    }
    d.fixed_gradient[v] = 1;
  }

  // Corners, incenters.
  double total_length = 0;
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int c = chart_triangles(f, k);
      if (c < 0 || c >= uv.rows()) {
        throw InvalidInput("spline_domain: face " + std::to_string(f) + " has chart vertex " +
                           std::to_string(c) + " outside the " + std::to_string(uv.rows()) +
                           " chart positions");
      }
      d.corner_uv(f, 2 * k) = uv(c, 0);
      d.corner_uv(f, 2 * k + 1) = uv(c, 1);
      d.referenced[topology.triangles(f, k)] = 1;
    }
    const Vec2 p0 = corner(d, f, 0), p1 = corner(d, f, 1), p2 = corner(d, f, 2);
    const double area2 = cross(p1 - p0, p2 - p0);
    if (!(area2 > 0) || !std::isfinite(area2)) {
      throw InvalidInput("spline_domain: face " + std::to_string(f) +
                         " has no positive area in its chart (twice the signed area " +
                         std::to_string(area2) + ")");
    }
    const Eigen::Vector3d side((p2 - p1).norm(), (p0 - p2).norm(), (p1 - p0).norm());
    total_length += side.sum();
    const Eigen::Vector3d w = side / side.sum();
    d.split_weights.row(f) = w.transpose();
    d.split_point.row(f) = (w[0] * p0 + w[1] * p1 + w[2] * p2).transpose();
  }
  d.mean_edge_length = nf > 0 ? total_length / (3.0 * nf) : 0;

  // Transitions across edges, split points on edges.
  for (int h = 0; h < 3 * nf; ++h) {
    const int h2 = topology.halfedge_twin[h];
    if (h2 < 0) continue;
    const int f = h / 3, k = h % 3, g = h2 / 3, k2 = h2 % 3;
    const int cp = chart_triangles(f, (k + 1) % 3), cq = chart_triangles(f, (k + 2) % 3);
    const int gp = chart_triangles(g, (k2 + 2) % 3), gq = chart_triangles(g, (k2 + 1) % 3);
    if (cp != gp || cq != gq) {
      const Complex pf = to_complex(corner(d, f, (k + 1) % 3));
      const Complex qf = to_complex(corner(d, f, (k + 2) % 3));
      const Complex pg = to_complex(corner(d, g, (k2 + 2) % 3));
      const Complex qg = to_complex(corner(d, g, (k2 + 1) % 3));
      Complex a = (qf - pf) / (qg - pg);
      a /= std::abs(a);
      d.halfedge_rotation[h] = a;
      d.halfedge_translation[h] = 0.5 * (pf + qf) - a * 0.5 * (pg + qg);
    }
    if (h > h2) continue;
    const Vec2 p = corner(d, f, (k + 1) % 3), q = corner(d, f, (k + 2) % 3);
    const Vec2 zf = d.split_point.row(f).transpose();
    const Vec2 zg = to_vec(d.halfedge_rotation[h] * to_complex(d.split_point.row(g).transpose()) +
                           d.halfedge_translation[h]);
    const double df = cross(q - p, zf - p), dg = cross(q - p, zg - p);
    if (!(df > 0) || !(dg < 0)) {
      throw InvalidInput("spline_domain: across edge " + std::to_string(topology.halfedge_edge[h]) +
                         " (faces " + std::to_string(f) + ", " + std::to_string(g) +
                         ") the incenters do not lie on opposite sides in the unfolded chart");
    }
    const Vec2 x = zf + df / (df - dg) * (zg - zf);
    const double mu = (x - p).dot(q - p) / (q - p).squaredNorm();
    const double lam = 1 - mu;
    if (!(lam > 0 && lam < 1)) {
      throw InvalidInput("spline_domain: the split point of edge " +
                         std::to_string(topology.halfedge_edge[h]) + " leaves the edge");
    }
    d.edge_split(f, k) = lam;
    d.edge_split(g, k2) = 1 - lam;
  }

  // Vertex frames: breadth-first around each vertex, rotating across cut edges.
  std::vector<std::vector<int>> vertex_corners(nv);
  for (int c = 0; c < 3 * nf; ++c) vertex_corners[topology.triangles(c / 3, c % 3)].push_back(c);
  std::vector<char> seen(3 * nf, 0);
  auto corner_at = [&](int face, int v) {
    for (int k = 0; k < 3; ++k) {
      if (topology.triangles(face, k) == v) return 3 * face + k;
    }
    return -1;
  };
  std::deque<int> queue;
  for (int v = 0; v < nv; ++v) {
    if (vertex_corners[v].empty()) continue;
    const int start = vertex_corners[v].front();
    seen[start] = 1;
    d.corner_frame[start] = 1;
    queue.assign(1, start);
    while (!queue.empty()) {
      const int c = queue.front();
      queue.pop_front();
      const int f = c / 3, k = c % 3;
      for (int h : {3 * f + (k + 1) % 3, 3 * f + (k + 2) % 3}) {
        const int h2 = topology.halfedge_twin[h];
        if (h2 < 0) continue;
        const int c2 = corner_at(h2 / 3, v);
        const Complex frame = std::conj(d.halfedge_rotation[h]) * d.corner_frame[c];
        if (seen[c2]) {
          if (!d.fixed_gradient[v]) {
            d.frame_closure_error =
                std::max(d.frame_closure_error, std::abs(std::arg(frame / d.corner_frame[c2])));
          }
          continue;
        }
        seen[c2] = 1;
        d.corner_frame[c2] = frame;
        queue.push_back(c2);
      }
    }
  }
  return d;
}

SplineDomain planar_spline_domain(const Triangles& triangles,
                                  const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv) {
  const Topology topology = build_topology(triangles, static_cast<int>(uv.rows()));
  return spline_domain(topology, triangles, uv, {});
}

Eigen::Matrix<double, kPowellSabinOrdinates, 9> face_ordinate_map(const SplineDomain& d, int f) {
  Eigen::Matrix<double, kPowellSabinOrdinates, 9> m = Eigen::Matrix<double, 19, 9>::Zero();
  const Vec2 z = d.split_point.row(f).transpose();
  // Row of "value at corner k plus its chart gradient dotted with w".
  auto add_taylor = [&](int row, int k, const Vec2& w, double weight) {
    m(row, k) += weight;
    // g_chart . w = (rho g_frame) . w = g_frame . (conj(rho) w)
    const Complex wf = std::conj(d.corner_frame[3 * f + k]) * to_complex(w);
    m(row, 3 + 2 * k) += weight * wf.real();
    m(row, 4 + 2 * k) += weight * wf.imag();
  };
  for (int k = 0; k < 3; ++k) {
    const Vec2 vk = corner(d, f, k);
    add_taylor(kA + k, k, Vec2::Zero(), 1);
    add_taylor(kC + k, k, (z - vk) / 2, 1);
  }
  for (int k = 0; k < 3; ++k) {
    const int kp = (k + 1) % 3, kq = (k + 2) % 3;
    const double lam = d.edge_split(f, k);
    const Vec2 r = split_on_side(d, f, k);
    add_taylor(kBP + k, kp, (r - corner(d, f, kp)) / 2, 1);
    add_taylor(kBQ + k, kq, (r - corner(d, f, kq)) / 2, 1);
    m.row(kD + k) = lam * m.row(kBP + k) + (1 - lam) * m.row(kBQ + k);
    m.row(kE + k) = lam * m.row(kC + kp) + (1 - lam) * m.row(kC + kq);
  }
  for (int k = 0; k < 3; ++k) m.row(kF) += d.split_weights(f, k) * m.row(kC + k);
  return m;
}

Eigen::Matrix<double, 3, kPowellSabinOrdinates> piece_hessian_map(const SplineDomain& d, int f,
                                                                  int piece) {
  const Eigen::Matrix<double, 3, 2> j = barycentric_gradients(piece_triangle(d, f, piece));
  const std::array<int, 6> s = piece_slots(piece);
  // b200 b020 b002 b110 b101 b011 -> barycentric index pairs
  constexpr int pa[6] = {0, 1, 2, 0, 0, 1};
  constexpr int pb[6] = {0, 1, 2, 1, 2, 2};
  Eigen::Matrix<double, 3, kPowellSabinOrdinates> h = Eigen::Matrix<double, 3, 19>::Zero();
  for (int i = 0; i < 6; ++i) {
    // H = sum_ab 2 b_ab J_a J_b^T over ordered pairs: off-diagonal ordinates appear twice.
    Eigen::Matrix2d outer = j.row(pa[i]).transpose() * j.row(pb[i]);
    if (pa[i] != pb[i]) outer += outer.transpose().eval();
    outer *= 2;
    h(0, s[i]) += outer(0, 0);
    h(1, s[i]) += outer(0, 1);
    h(2, s[i]) += outer(1, 1);
  }
  return h;
}

Eigen::MatrixXd face_ordinates(const SplineDomain& d, const SplineVertexData& data) {
  const int k = static_cast<int>(data.values.cols());
  if (data.values.rows() != d.num_vertices || data.gradients.rows() != d.num_vertices ||
      data.gradients.cols() != 2 * k) {
    throw InvalidInput("face_ordinates: vertex data must be #V = " +
                       std::to_string(d.num_vertices) + " rows of k values and 2k gradients");
  }
  const int nf = static_cast<int>(d.triangles.rows());
  Eigen::MatrixXd ord(kPowellSabinOrdinates * nf, k);
  Eigen::Matrix<double, 9, Eigen::Dynamic> local(9, k);
  for (int f = 0; f < nf; ++f) {
    for (int c = 0; c < 3; ++c) {
      const int v = d.triangles(f, c);
      local.row(c) = data.values.row(v);
      for (int col = 0; col < k; ++col) {
        local(3 + 2 * c, col) = data.gradients(v, 2 * col);
        local(4 + 2 * c, col) = data.gradients(v, 2 * col + 1);
      }
    }
    ord.middleRows(kPowellSabinOrdinates * f, kPowellSabinOrdinates) =
        face_ordinate_map(d, f) * local;
  }
  return ord;
}

SplineSample evaluate_spline(const SplineDomain& d, const Eigen::MatrixXd& ordinates, int f,
                             const Eigen::Vector3d& barycentric) {
  const Vec2 x = barycentric[0] * corner(d, f, 0) + barycentric[1] * corner(d, f, 1) +
                 barycentric[2] * corner(d, f, 2);
  int best = 0;
  double best_min = -1e300;
  Eigen::Vector3d best_l = Eigen::Vector3d::Zero();
  for (int p = 0; p < kPowellSabinPieces; ++p) {
    const Eigen::Vector3d l = barycentric_in(piece_triangle(d, f, p), x);
    if (l.minCoeff() > best_min) {
      best_min = l.minCoeff();
      best = p;
      best_l = l;
    }
  }
  const std::array<int, 6> s = piece_slots(best);
  const int k = static_cast<int>(ordinates.cols());
  auto b = [&](int i) { return ordinates.row(kPowellSabinOrdinates * f + s[i]); };
  const Eigen::Vector3d& l = best_l;
  SplineSample out;
  out.piece = best;
  out.value = b(0) * (l[0] * l[0]) + b(1) * (l[1] * l[1]) + b(2) * (l[2] * l[2]) +
              b(3) * (2 * l[0] * l[1]) + b(4) * (2 * l[0] * l[2]) + b(5) * (2 * l[1] * l[2]);
  // d/dl_a of the quadratic form: 2 sum_b B_ab l_b
  Eigen::Matrix<double, 3, Eigen::Dynamic> dl(3, k);
  dl.row(0) = 2 * (b(0) * l[0] + b(3) * l[1] + b(4) * l[2]);
  dl.row(1) = 2 * (b(3) * l[0] + b(1) * l[1] + b(5) * l[2]);
  dl.row(2) = 2 * (b(4) * l[0] + b(5) * l[1] + b(2) * l[2]);
  out.gradient = barycentric_gradients(piece_triangle(d, f, best)).transpose() * dl;
  return out;
}

ContinuityReport measure_continuity(const SplineDomain& d, const Eigen::MatrixXd& ordinates,
                                    int samples_per_edge) {
  ContinuityReport r;
  const int k = static_cast<int>(ordinates.cols());
  for (int c = 0; c < k; ++c) {
    r.value_scale =
        std::max(r.value_scale, ordinates.col(c).maxCoeff() - ordinates.col(c).minCoeff());
  }
  std::vector<double> edge_value_jump(d.num_edges, 0), edge_gradient_jump(d.num_edges, 0);
  const int nh = static_cast<int>(d.halfedge_twin.size());
  for (int h = 0; h < nh; ++h) {
    const int h2 = d.halfedge_twin[h];
    if (h2 < 0 || h2 < h) continue;
    const int f = h / 3, kf = h % 3, g = h2 / 3, kg = h2 % 3;
    const Complex rot = d.halfedge_rotation[h];
    ++r.edges_checked;
    for (int i = 1; i <= samples_per_edge; ++i) {
      const double t = static_cast<double>(i) / (samples_per_edge + 1);
      Eigen::Vector3d bf = Eigen::Vector3d::Zero(), bg = Eigen::Vector3d::Zero();
      bf[(kf + 1) % 3] = 1 - t;
      bf[(kf + 2) % 3] = t;
      bg[(kg + 2) % 3] = 1 - t;
      bg[(kg + 1) % 3] = t;
      const SplineSample sf = evaluate_spline(d, ordinates, f, bf);
      const SplineSample sg = evaluate_spline(d, ordinates, g, bg);
      ++r.samples;
      const int e = d.halfedge_edge[h];
      for (int col = 0; col < k; ++col) {
        const Vec2 gf = sf.gradient.col(col);
        const Vec2 gg = to_vec(rot * to_complex(sg.gradient.col(col)));
        r.gradient_scale = std::max({r.gradient_scale, gf.norm(), gg.norm()});
        edge_value_jump[e] = std::max(edge_value_jump[e], std::abs(sf.value[col] - sg.value[col]));
        edge_gradient_jump[e] = std::max(edge_gradient_jump[e], (gf - gg).norm());
      }
      r.max_value_jump = std::max(r.max_value_jump, edge_value_jump[e]);
      r.max_gradient_jump = std::max(r.max_gradient_jump, edge_gradient_jump[e]);
    }
  }
  r.relative_value_jump = r.value_scale > 0 ? r.max_value_jump / r.value_scale : r.max_value_jump;
  r.relative_gradient_jump =
      r.gradient_scale > 0 ? r.max_gradient_jump / r.gradient_scale : r.max_gradient_jump;
  double worst = -1;
  for (int e = 0; e < d.num_edges; ++e) {
    const double rel = std::max(edge_value_jump[e] / std::max(r.value_scale, kTinyScale),
                                edge_gradient_jump[e] / std::max(r.gradient_scale, kTinyScale));
    if (rel > worst && (edge_value_jump[e] > 0 || edge_gradient_jump[e] > 0)) {
      worst = rel;
      r.worst_edge = e;
    }
  }
  return r;
}

}  // namespace ricci
