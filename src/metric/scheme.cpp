#include "ricci/metric/scheme.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "ricci/errors.hpp"
#include "ricci/mesh/build_counts.hpp"
#include "ricci/metric/hyperbolic.hpp"

namespace ricci {
namespace {

/// The per-vertex fit's safeguarded Newton stops once its bracket is this small relative to its
/// upper end (a few ulps: the radius is then exact to double) or after kMaxFitIterations steps
/// (bisection alone halves the bracket 60 times: 1e-18 of its start).
constexpr double kFitBracket = 1e-15;
constexpr int kMaxFitIterations = 60;
/// Keeps fitted radii and residuals positive (their logs are taken) without changing any that
/// double can tell from zero.
constexpr double kTinyPositive = 1e-300;
/// The tangential fit's smallest radius, relative to the mean edge length: a radius may not
/// vanish (its log is u), and a millionth of an edge keeps the lengths a + b exact to 1e-6.
constexpr double kTangentialRadiusFloor = 1e-6;

/// Vertex -> incident edges, compressed rows.
struct VertexEdges {
  std::vector<int> offsets, edges;
};

VertexEdges vertex_edges(const Topology& t) {
  VertexEdges ve;
  ve.offsets.assign(t.num_vertices + 1, 0);
  for (int e = 0; e < t.num_edges; ++e) {
    ++ve.offsets[t.edge_vertices(e, 0) + 1];
    ++ve.offsets[t.edge_vertices(e, 1) + 1];
  }
  for (int v = 0; v < t.num_vertices; ++v) ve.offsets[v + 1] += ve.offsets[v];
  ve.edges.resize(ve.offsets.back());
  std::vector<int> fill(ve.offsets.begin(), ve.offsets.end() - 1);
  for (int e = 0; e < t.num_edges; ++e) {
    ve.edges[fill[t.edge_vertices(e, 0)]++] = e;
    ve.edges[fill[t.edge_vertices(e, 1)]++] = e;
  }
  return ve;
}

int other_end(const Topology& t, int e, int v) {
  return t.edge_vertices(e, 0) == v ? t.edge_vertices(e, 1) : t.edge_vertices(e, 0);
}

/// Length of a Thurston edge with radii x, g whose Phi is the best one in [0, Phi_max] for the
/// target length L (c = cos Phi_max): the target clamped to [sqrt(x^2 + g^2 + 2 c x g), x + g].
double thurston_fit_length(double x, double g, double target, double c) {
  return std::clamp(target, std::sqrt(x * x + g * g + 2 * c * x * g), x + g);
}

/// Minimises over x > 0 the sum over the edges of a vertex of (l(x) - lbar)^2, where l(x) is the
/// best Thurston length above. Each term is convex in x (zero where lbar can be met,
/// (lbar - x - g)^2 below, (sqrt(x^2 + g^2 + 2 c x g) - lbar)^2 above), so a safeguarded Newton
/// iteration on the derivative finds the minimiser nearest the current radius.
double fit_thurston_radius(double x, const std::vector<std::pair<double, double>>& neighbours,
                           double c) {
  auto derivatives = [&](double y, double& d1, double& d2) {
    d1 = d2 = 0;
    for (const auto& [g, target] : neighbours) {
      const double shortest_sq = y * y + g * g + 2 * c * y * g;
      if (y + g < target) {
        d1 += -2.0 * (target - y - g);
        d2 += 2.0;
      } else if (shortest_sq > target * target) {
        const double r = std::sqrt(shortest_sq);
        const double slope = (y + c * g) / r;
        d1 += 2.0 * (r - target) * slope;
        d2 += 2.0 * (slope * slope + (r - target) * (1 - c * c) * g * g / (r * r * r));
      }
    }
  };
  double d1, d2;
  derivatives(x, d1, d2);
  if (d1 == 0) return x;
  double lo = 0, hi = 0;
  for (const auto& n : neighbours) hi = std::max(hi, n.second);
  if (d1 > 0)
    hi = x;
  else
    lo = x;
  for (int iteration = 0; iteration < kMaxFitIterations && hi - lo > kFitBracket * hi;
       ++iteration) {
    double next = d2 > 0 ? x - d1 / d2 : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    x = next;
    derivatives(x, d1, d2);
    if (d1 == 0) break;
    if (d1 > 0)
      hi = x;
    else
      lo = x;
  }
  return std::max(x, kTinyPositive);
}

/// Gauss-Seidel sweeps of the per-vertex fit; returns the sweeps used.
template <class FittedLength, class FitVertex>
int fit_sweeps(const Topology& t, const VertexEdges& ve, const Eigen::VectorXd& lbar,
               Eigen::VectorXd& gamma, const StructureOptions& options, FittedLength fitted_length,
               FitVertex fit_vertex) {
  auto residual = [&]() {
    double sum = 0;
    for (int e = 0; e < t.num_edges; ++e) {
      const double l =
          fitted_length(gamma[t.edge_vertices(e, 0)], gamma[t.edge_vertices(e, 1)], lbar[e]);
      sum += (l - lbar[e]) * (l - lbar[e]);
    }
    return sum;
  };
  double previous = residual();
  std::vector<std::pair<double, double>> neighbours;
  int sweep = 0;
  while (sweep < options.fit_sweeps && previous > 0) {
    ++sweep;
    for (int v = 0; v < t.num_vertices; ++v) {
      if (ve.offsets[v] == ve.offsets[v + 1]) continue;
      neighbours.clear();
      for (int p = ve.offsets[v]; p < ve.offsets[v + 1]; ++p) {
        const int e = ve.edges[p];
        neighbours.emplace_back(gamma[other_end(t, e, v)], lbar[e]);
      }
      gamma[v] = fit_vertex(gamma[v], neighbours);
    }
    const double current = residual();
    const double improvement = previous - current;
    previous = current;
    if (improvement <= options.fit_tolerance * std::max(current, kTinyPositive)) break;
  }
  return sweep;
}

}  // namespace

const SchemeTraits& scheme_traits(Scheme scheme) {
  for (const SchemeTraits& row : kSchemeTraits) {
    if (row.scheme == scheme) return row;
  }
  throw InvalidInput("scheme_traits: no scheme " + std::to_string(static_cast<int>(scheme)));
}

double max_face_angle(const SchemeTraits& traits, double eta) {
  const double phi = traits.circle_packing ? std::acos(std::clamp(eta, -1.0, 1.0)) : 0.0;
  return std::numbers::pi - phi;
}

const char* scheme_name(Scheme scheme) {
  return enum_name(scheme);
}

Scheme parse_scheme(const std::string& name) {
  return parse_enum<Scheme>(name, "parse_scheme");
}

Eigen::VectorXd input_edge_lengths(const Mesh& mesh, const Topology& topology) {
  const build_counting::Scope counted(build_counting::Kind::InputLengths);
  Eigen::VectorXd lengths(topology.num_edges);
  for (int e = 0; e < topology.num_edges; ++e) {
    lengths[e] = (mesh.positions.row(topology.edge_vertices(e, 0)) -
                  mesh.positions.row(topology.edge_vertices(e, 1)))
                     .norm();
  }
  return lengths;
}

StructureResult make_conformal_structure(const Topology& t, const Eigen::VectorXd& lbar,
                                         const StructureOptions& options) {
  if (lbar.size() != t.num_edges) {
    throw InvalidInput("make_conformal_structure: " + std::to_string(lbar.size()) +
                       " lengths given for " + std::to_string(t.num_edges) + " edges");
  }
  for (int e = 0; e < t.num_edges; ++e) {
    if (!(lbar[e] > 0) || !std::isfinite(lbar[e])) {
      throw InvalidInput("make_conformal_structure: edge " + std::to_string(e) + " (" +
                         std::to_string(t.edge_vertices(e, 0)) + ", " +
                         std::to_string(t.edge_vertices(e, 1)) + ") has length " +
                         std::to_string(lbar[e]));
    }
  }
  // (The hyperbolic structure is made from a Euclidean one, counted there.)
  if (options.geometry == Geometry::Hyperbolic) return make_hyperbolic_structure(t, lbar, options);
  const build_counting::Scope counted(build_counting::Kind::Structure);
  const int nv = t.num_vertices, ne = t.num_edges;
  // Each vertex's edges: for the schemes that fit radii to the lengths (vertex scaling starts
  // from gamma = 1 and needs none).
  const VertexEdges ve = options.scheme == Scheme::VertexScaling ? VertexEdges{} : vertex_edges(t);
  StructureResult result;
  ConformalStructure& s = result.structure;
  s.scheme = options.scheme;
  s.epsilon.setConstant(nv, scheme_traits(options.scheme).epsilon);
  s.eta.resize(ne);
  Eigen::VectorXd gamma = Eigen::VectorXd::Ones(nv);

  auto adjacent = [&](int v, bool take_min) {
    double acc = take_min ? INFINITY : 0.0;
    const int count = ve.offsets[v + 1] - ve.offsets[v];
    for (int p = ve.offsets[v]; p < ve.offsets[v + 1]; ++p) {
      acc = take_min ? std::min(acc, lbar[ve.edges[p]]) : acc + lbar[ve.edges[p]];
    }
    return count == 0 ? 1.0 : (take_min ? acc : acc / count);
  };

  switch (options.scheme) {
    case Scheme::Thurston:
    case Scheme::Tangential: {
      const bool thurston = options.scheme == Scheme::Thurston;
      // Thurston packings fit Phi in [0, max_intersection_angle]: eta = cos Phi >= c.
      const double c =
          std::cos(std::clamp(options.max_intersection_angle, 0.0, std::numbers::pi / 2));
      if (options.packing_init == PackingInit::UnitRadii) {
        s.eta.setOnes();
        break;
      }
      // Equal radii c lbar / 2 fit an edge exactly for c in [1, sqrt 2]; start inside that range.
      for (int v = 0; v < nv; ++v) gamma[v] = (thurston ? 0.6 : 0.5) * adjacent(v, false);
      if (thurston) {
        result.fit_sweeps = fit_sweeps(
            t, ve, lbar, gamma, options,
            [c](double a, double b, double l) { return thurston_fit_length(a, b, l, c); },
            [c](double r, const std::vector<std::pair<double, double>>& nb) {
              return fit_thurston_radius(r, nb, c);
            });
      } else {
        // Tangential lengths are gamma_i + gamma_j: each vertex step is a 1-D least squares.
        double floor = kTangentialRadiusFloor * lbar.mean();
        result.fit_sweeps = fit_sweeps(
            t, ve, lbar, gamma, options, [](double a, double b, double) { return a + b; },
            [floor](double, const std::vector<std::pair<double, double>>& nb) {
              double sum = 0;
              for (const auto& [g, target] : nb) sum += target - g;
              return std::max(sum / static_cast<double>(nb.size()), floor);
            });
      }
      for (int e = 0; e < ne; ++e) {
        const double gi = gamma[t.edge_vertices(e, 0)], gj = gamma[t.edge_vertices(e, 1)];
        const double cos_phi = (lbar[e] * lbar[e] - gi * gi - gj * gj) / (2 * gi * gj);
        s.eta[e] = thurston ? std::clamp(cos_phi, c, 1.0) : 1.0;
      }
      break;
    }
    case Scheme::InversiveDistance:
    case Scheme::VirtualRadius: {
      // Radii a third of the shortest incident edge: circles of neighbours stay disjoint
      // (inversive distance > 1), which is the regime where the flow is best behaved.
      for (int v = 0; v < nv; ++v) gamma[v] = adjacent(v, true) / 3.0;
      const double sign = options.scheme == Scheme::InversiveDistance ? -1.0 : 1.0;
      for (int e = 0; e < ne; ++e) {
        const double gi = gamma[t.edge_vertices(e, 0)], gj = gamma[t.edge_vertices(e, 1)];
        s.eta[e] = (lbar[e] * lbar[e] + sign * (gi * gi + gj * gj)) / (2 * gi * gj);
      }
      break;
    }
    case Scheme::VertexScaling:
      for (int e = 0; e < ne; ++e) s.eta[e] = 0.5 * lbar[e] * lbar[e];
      break;
  }
  s.initial_u = gamma.array().log().matrix();

  double sum_sq = 0, sum_ref = 0, max_rel = 0;
  for (int e = 0; e < ne; ++e) {
    const int i = t.edge_vertices(e, 0), j = t.edge_vertices(e, 1);
    const double l =
        std::sqrt(s.epsilon[i] * gamma[i] * gamma[i] + s.epsilon[j] * gamma[j] * gamma[j] +
                  2 * s.eta[e] * gamma[i] * gamma[j]);
    sum_sq += (l - lbar[e]) * (l - lbar[e]);
    sum_ref += lbar[e] * lbar[e];
    max_rel = std::max(max_rel, std::abs(l - lbar[e]) / lbar[e]);
  }
  result.fit_rms_relative_error = ne > 0 ? std::sqrt(sum_sq / sum_ref) : 0.0;
  result.fit_max_relative_error = max_rel;
  return result;
}

}  // namespace ricci
