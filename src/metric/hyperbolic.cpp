#include "ricci/metric/hyperbolic.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "metric/detail/triangle_terms.hpp"
#include "ricci/errors.hpp"
#include "ricci/metric/curvature.hpp"

namespace ricci {

double hyperbolic_radius(double u) {
  if (!(u < 0)) return std::numeric_limits<double>::quiet_NaN();
  return 2.0 * std::atanh(std::exp(u));
}

double hyperbolic_log_radius(double r) {
  return std::log(std::tanh(0.5 * r));
}

double hyperbolic_edge_length(double r_i, double r_j, double eta) {
  const double c = std::cosh(r_i) * std::cosh(r_j) + eta * std::sinh(r_i) * std::sinh(r_j);
  if (!(c >= 1.0)) return std::numeric_limits<double>::quiet_NaN();
  return std::acosh(c);
}

double hyperbolic_angle_from_lengths(double a, double b, double c) {
  const double l[3] = {a, b, c};
  double two_s, d[3], theta[3];
  if (!triangle_terms::half_perimeter_terms(l, two_s, d)) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  triangle_terms::hyperbolic_angles(two_s, d, theta);
  return theta[0];
}

namespace {

using triangle_terms::hyperbolic_edge;

/// Lengths 2 asinh(sqrt(q)) in any precision (NaN where no length exists).
template <class T, class Vector>
LengthsCheck lengths_in(const Topology& topology, const ConformalStructure& structure,
                        const Vector& u, Vector& lengths) {
  lengths.resize(topology.num_edges);
  LengthsCheck check;
  for (int e = 0; e < topology.num_edges; ++e) {
    const int i = topology.edge_vertices(e, 0), j = topology.edge_vertices(e, 1);
    const auto t = hyperbolic_edge<T>(u[i], u[j], structure.epsilon[i], structure.epsilon[j],
                                      structure.eta[e]);
    if (t.valid()) {
      lengths[e] = 2 * std::asinh(std::sqrt(t.q));
    } else {
      lengths[e] = std::numeric_limits<T>::quiet_NaN();
      if (check.invalid_edges++ == 0) check.first_edge = e;
    }
  }
  return check;
}

/// cosh(x) - 1 without cancellation.
double cosh_minus_one(double x) {
  const double h = std::sinh(0.5 * x);
  return 2.0 * h * h;
}

}  // namespace

LengthsCheck hyperbolic_edge_lengths(const Topology& topology, const ConformalStructure& structure,
                                     const Eigen::VectorXd& u, Eigen::VectorXd& lengths) {
  return lengths_in<double>(topology, structure, u, lengths);
}

LengthsCheck hyperbolic_edge_lengths_wide(const Topology& topology,
                                          const ConformalStructure& structure, const WideVector& u,
                                          WideVector& lengths) {
  return lengths_in<long double>(topology, structure, u, lengths);
}

AnglesCheck hyperbolic_corner_angles(const Topology& topology, const Eigen::VectorXd& lengths,
                                     CornerAngles& angles) {
  return {triangle_terms::corner_angles_with<double>(topology, lengths, angles,
                                                     triangle_terms::hyperbolic_angles<double>)};
}

AnglesCheck hyperbolic_corner_angles_wide(const Topology& topology, const WideVector& lengths,
                                          WideAngles& angles) {
  return {triangle_terms::corner_angles_with<long double>(
      topology, lengths, angles, triangle_terms::hyperbolic_angles<long double>)};
}

Eigen::Vector2d hyperbolic_length_derivatives(double u_i, double u_j, double epsilon_i,
                                              double epsilon_j, double eta, double length) {
  const auto t = hyperbolic_edge<double>(u_i, u_j, epsilon_i, epsilon_j, eta);
  const double d = t.fi * t.fj;
  // dq/du_i = (d numerator / du_i) / D - q (dD/du_i) / D, with dD/du_i / D = -2 eps_i t_i^2 / f_i;
  // dq/dl = sinh(l) / 2.
  const double ai = epsilon_i * t.ti * t.ti, aj = epsilon_j * t.tj * t.tj;
  const double cross = 2.0 * eta * t.ti * t.tj;
  const double dq_i = (2.0 * ai + cross) / d + t.q * 2.0 * ai / t.fi;
  const double dq_j = (2.0 * aj + cross) / d + t.q * 2.0 * aj / t.fj;
  const double factor = 2.0 / std::sinh(length);
  return {factor * dq_i, factor * dq_j};
}

Eigen::Matrix3d hyperbolic_face_jacobian(const Topology& topology,
                                         const ConformalStructure& structure,
                                         const Eigen::VectorXd& u, const Eigen::VectorXd& lengths,
                                         const CornerAngles& angles, int f) {
  double l[3], sh[3], cs[3];
  int v[3];
  for (int k = 0; k < 3; ++k) {
    l[k] = lengths[topology.face_edges(f, k)];
    sh[k] = std::sinh(l[k]);
    cs[k] = std::cos(angles(f, k));
    v[k] = topology.triangles(f, k);
  }
  // dtheta / dl: row i, column = edge opposite corner column.
  Eigen::Matrix3d a;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    const double d = sh[i] / (sh[j] * sh[k] * std::sin(angles(f, i)));
    a(i, i) = d;
    a(i, j) = -d * cs[k];
    a(i, k) = -d * cs[j];
  }
  // dl / du: row = edge opposite corner, column = corner.
  Eigen::Matrix3d b = Eigen::Matrix3d::Zero();
  for (int k = 0; k < 3; ++k) {
    const int e = topology.face_edges(f, k);
    const int p = (k + 1) % 3, q = (k + 2) % 3;
    const Eigen::Vector2d dl = hyperbolic_length_derivatives(
        u[v[p]], u[v[q]], structure.epsilon[v[p]], structure.epsilon[v[q]], structure.eta[e], l[k]);
    b(k, p) = dl[0];
    b(k, q) = dl[1];
  }
  return a * b;
}

void hyperbolic_hessian_terms(const Topology& topology, const ConformalStructure& structure,
                              const Eigen::VectorXd& u, const Eigen::VectorXd& lengths,
                              const CornerAngles& angles, Eigen::VectorXd& weights,
                              Eigen::VectorXd& corner_diagonal) {
  const int nf = topology.num_faces;
  weights.resize(3 * static_cast<Eigen::Index>(nf));
  corner_diagonal.resize(3 * static_cast<Eigen::Index>(nf));
  for (int f = 0; f < nf; ++f) {
    const Eigen::Matrix3d j = hyperbolic_face_jacobian(topology, structure, u, lengths, angles, f);
    for (int k = 0; k < 3; ++k) {
      const int p = (k + 1) % 3, q = (k + 2) % 3;
      weights[3 * f + k] = 0.5 * (j(p, q) + j(q, p));
      corner_diagonal[3 * f + k] = -j.row(k).sum();
    }
  }
}

double hyperbolic_total_area(const CornerAngles& angles) {
  Eigen::VectorXd area(angles.rows());
  for (Eigen::Index f = 0; f < angles.rows(); ++f) area[f] = std::numbers::pi - angles.row(f).sum();
  return accurate_sum(area);
}

double hyperbolic_length_scale(const Topology& t, const Eigen::VectorXd& lbar, double requested) {
  if (requested > 0) {
    if (!std::isfinite(requested)) {
      throw InvalidInput("hyperbolic_length_scale: the scale must be finite");
    }
    return requested;
  }
  if (requested < 0) {
    throw InvalidInput("hyperbolic_length_scale: the scale must be positive (or 0 for automatic)");
  }
  double area = 0;
  for (int f = 0; f < t.num_faces; ++f) {
    const double a = lbar[t.face_edges(f, 0)], b = lbar[t.face_edges(f, 1)],
                 c = lbar[t.face_edges(f, 2)];
    const double s = 0.5 * (a + b + c);
    area += std::sqrt(std::max(0.0, s * (s - a) * (s - b) * (s - c)));
  }
  int chi = 0;
  for (const Component& c : t.components) chi += c.euler_characteristic;
  const double wanted = chi != 0 ? 2.0 * std::numbers::pi * std::abs(chi) : 4.0 * std::numbers::pi;
  if (!(area > 0)) throw InvalidInput("hyperbolic_length_scale: the mesh has no area");
  return std::sqrt(wanted / area);
}

StructureResult make_hyperbolic_structure(const Topology& t, const Eigen::VectorXd& lbar,
                                          const StructureOptions& options) {
  if (!scheme_traits(options.scheme).hyperbolic) {
    // Virtual radius: its hyperbolic Hessian is indefinite already at the fitted metric (measured
    // on a generated genus-2 surface: eigenvalues down to -1.8), so Newton has no convex energy
    // to descend.
    std::vector<const char*> offered;
    for (const SchemeTraits& row : kSchemeTraits) {
      if (row.hyperbolic) offered.push_back(row.name);
    }
    std::string list;
    for (std::size_t i = 0; i < offered.size(); ++i) {
      list += (i == 0 ? "" : i + 1 == offered.size() ? " or " : ", ") + std::string(offered[i]);
    }
    throw InvalidInput("make_conformal_structure: the " + std::string(scheme_name(options.scheme)) +
                       " scheme has no convex Ricci energy in the hyperbolic background; use " +
                       list);
  }
  const double scale = hyperbolic_length_scale(t, lbar, options.hyperbolic_length_scale);
  const Eigen::VectorXd big_l = scale * lbar;
  StructureOptions flat = options;
  flat.geometry = Geometry::Euclidean;
  // The Euclidean fit of the scaled lengths gives the radii (and eta where it stays).
  StructureResult result = make_conformal_structure(t, big_l, flat);
  ConformalStructure& s = result.structure;
  s.geometry = Geometry::Hyperbolic;
  s.length_scale = scale;
  const int nv = t.num_vertices, ne = t.num_edges;
  const bool unit = options.packing_init == PackingInit::UnitRadii;
  switch (options.scheme) {
    case Scheme::Thurston:
    case Scheme::Tangential:
    case Scheme::InversiveDistance: {
      const Eigen::VectorXd r = s.initial_u.array().exp().matrix();
      const double c =
          std::cos(std::clamp(options.max_intersection_angle, 0.0, std::numbers::pi / 2));
      for (int e = 0; e < ne; ++e) {
        const double ri = r[t.edge_vertices(e, 0)], rj = r[t.edge_vertices(e, 1)];
        if (options.scheme == Scheme::Tangential || unit) {
          s.eta[e] = 1.0;
          continue;
        }
        // eta = (cosh L - cosh r_i cosh r_j) / (sinh r_i sinh r_j), every cosh - 1 exact.
        const double ci = cosh_minus_one(ri), cj = cosh_minus_one(rj);
        const double eta =
            (cosh_minus_one(big_l[e]) - (ci * cj + ci + cj)) / (std::sinh(ri) * std::sinh(rj));
        s.eta[e] = options.scheme == Scheme::Thurston ? std::clamp(eta, c, 1.0) : eta;
      }
      for (int v = 0; v < nv; ++v) s.initial_u[v] = hyperbolic_log_radius(r[v]);
      break;
    }
    case Scheme::VertexScaling:
      for (int e = 0; e < ne; ++e) {
        const double h = std::sinh(0.5 * big_l[e]);
        s.eta[e] = 0.5 * h * h;
      }
      s.initial_u.setZero(nv);
      break;
    case Scheme::VirtualRadius:
      break;  // refused above
  }
  Eigen::VectorXd l;
  hyperbolic_edge_lengths(t, s, s.initial_u, l);
  double sum_sq = 0, sum_ref = 0, max_rel = 0;
  for (int e = 0; e < ne; ++e) {
    const double d = l[e] - big_l[e];
    sum_sq += d * d;
    sum_ref += big_l[e] * big_l[e];
    max_rel = std::max(max_rel, std::abs(d) / big_l[e]);
  }
  result.fit_rms_relative_error = ne > 0 ? std::sqrt(sum_sq / sum_ref) : 0.0;
  result.fit_max_relative_error = max_rel;
  return result;
}

}  // namespace ricci
