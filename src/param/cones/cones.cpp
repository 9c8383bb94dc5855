#include "ricci/param/cones/cones.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Dense>
#include <numbers>

#include "param/cones/detail/cone_objective.hpp"
#include "param/cones/detail/cone_selection_steps.hpp"
#include "param/cones/detail/linear_flow.hpp"
#include "ricci/errors.hpp"
#include "ricci/intrinsic/delaunay_flips.hpp"
#include "ricci/intrinsic/intrinsic_triangulation.hpp"
#include "ricci/mesh/build_counts.hpp"
#include "ricci/metric/curvature.hpp"
#include "ricci/metric/hessian.hpp"
#include "ricci/metric/lengths.hpp"
#include "ricci/numerics/bounded_least_squares.hpp"
#include "ricci/numerics/sparse_cholesky.hpp"

namespace ricci {

using cone_steps::area_energy;
using cone_steps::ConeModelData;
using cone_steps::ConeObjective;
using cone_steps::face_areas;
using cone_steps::kFarFromCones;
using cone_steps::kSeparationRings;
using cone_steps::LinearFlow;
using cone_steps::linearise_flow;
using cone_steps::vertex_neighbours;

namespace {

/// Floor of the area weight log_scale_spread's mean divides by: no vertex away from the cones
/// gives a mean of 0, not a division by zero.
constexpr double kSmallestWeight = 1e-300;

/// The penalty that holds a vertex at u = 0, relative to the largest diagonal entry of the
/// Laplacian (at least 1): large enough that a held vertex's u is about 1e-10 of its
/// neighbours' (held as if exactly), and a large diagonal entry costs the Cholesky factorisation
/// no accuracy.
constexpr double kHeldPenalty = 1e10;

/// Whether L plus a large penalty on vertex 0 (the gauge) factorises: a connected component's
/// Laplacian with non-negative enough weights does.
bool positive_definite_with_one_pin(const Eigen::SparseMatrix<double>& L) {
  Eigen::SparseMatrix<double> A = L;
  A.coeffRef(0, 0) += kHeldPenalty * std::max(1.0, L.diagonal().cwiseAbs().maxCoeff());
  SparseCholesky cholesky;
  try {
    cholesky.factorize(A);
  } catch (const SolverError&) {
    return false;
  }
  return true;
}

/// The cotangent Laplacian of the input metric's intrinsic Delaunay triangulation (#V by #V).
/// \param s the input lengths' vertex-scaling structure
Eigen::SparseMatrix<double> intrinsic_delaunay_laplacian(const Topology& t,
                                                         const Eigen::VectorXd& input_lengths,
                                                         ConformalStructure s) {
  Eigen::VectorXd lengths = input_lengths;
  const Eigen::VectorXd u = s.initial_u;
  // (t is copied only when some edge is not Delaunay.)
  IntrinsicTriangulation intrinsic(t, std::move(s));
  DelaunayFlipOptions isometric;
  isometric.isometric = true;
  intrinsic.flip_to_delaunay(u, lengths, isometric);
  const Topology& flipped = intrinsic.topology();
  CornerAngles angles;
  corner_angles(flipped, lengths, angles);
  Eigen::VectorXd hw, ew;
  halfedge_weights(flipped, intrinsic.structure(), u, lengths, angles, hw);
  edge_weights(flipped, hw, ew);
  return curvature_hessian(flipped, ew);
}

/// grow_rings, but a ring is only taken while the area the source's rings cover (area: per
/// vertex, normalised to a total of 1) stays within max_area: on a CAD mesh one ring of a fan
/// centre covers a whole face of the part, and three rings the whole part.
void grow_rings_within(const std::vector<std::vector<int>>& neighbours, int source, int max_rings,
                       const Eigen::VectorXd& area, double max_area, std::vector<int>& hops) {
  std::vector<int> frontier = {source};
  hops[source] = 0;
  double covered = area[source];
  for (int r = 1; r <= max_rings && !frontier.empty(); ++r) {
    std::vector<int> next;
    std::vector<int> before;  // their hops before this ring, to undo it
    double added = 0;
    for (int a : frontier) {
      for (int b : neighbours[a]) {
        if (hops[b] > r) {
          before.push_back(hops[b]);
          hops[b] = r;
          next.push_back(b);
          added += area[b];
        }
      }
    }
    if (covered + added > max_area) {
      for (std::size_t i = next.size(); i-- > 0;) hops[next[i]] = before[i];
      return;
    }
    covered += added;
    frontier = std::move(next);
  }
}

/// A cone set of at most this many cones is improved by exchanges (each cone taken out and
/// the best candidate put in): two passes over the cones up to kExchangeTwice of them, one pass
/// above (an exchange costs two fits of #V x #S each; kitten with 32 cones: 6.1 s for two passes
/// against 1.4 s for the greedy alone).
/// (kExchangeTwice: cone_selection_steps.cpp.)
constexpr int kExchangeCones = 64;

/// log_scale_spread leaves out at most this fraction of the area around each cone: with three
/// whole rings, a CAD cylinder's fan centres hid every vertex and the spread read 0.
constexpr double kRingArea = 0.02;

/// A third of each vertex's faces' share of the 3D area (summing to 1).
Eigen::VectorXd vertex_areas(const Topology& t, const Eigen::VectorXd& face_area) {
  Eigen::VectorXd area = Eigen::VectorXd::Zero(t.num_vertices);
  for (int f = 0; f < t.num_faces; ++f) {
    for (int k = 0; k < 3; ++k) area[t.triangles(f, k)] += face_area[f] / 3;
  }
  return area;
}

void check_cone_options(const ConeSelectionOptions& options) {
  if (options.count < 0 || options.max_cones < 0 || !(options.max_log_scale > 0) ||
      !(options.max_face_angle > 0) || !(options.max_corner_angle > 0) ||
      !(options.max_curvature < 2 * std::numbers::pi) || !(options.smoothness >= 0)) {
    throw InvalidInput(
        "select_cones: count and max_cones must be >= 0, max_log_scale, max_face_angle and "
        "max_corner_angle > 0, max_curvature < 2 pi, smoothness >= 0");
  }
}

}  // namespace

namespace cone_steps {

Eigen::VectorXd face_areas(const Mesh& mesh, const Topology& t) {
  Eigen::VectorXd area(t.num_faces);
  for (int f = 0; f < t.num_faces; ++f) {
    const Eigen::Vector3d a = mesh.positions.row(t.triangles(f, 0));
    const Eigen::Vector3d b = mesh.positions.row(t.triangles(f, 1));
    const Eigen::Vector3d c = mesh.positions.row(t.triangles(f, 2));
    area[f] = (b - a).cross(c - a).norm();
  }
  return area / area.sum();
}

LinearFlow linearise_flow(const FlowProblem& problem, const char* who) {
  const Topology& t = problem.topology;
  const ConformalStructure& s = problem.structure.structure;
  LinearFlow linear;
  // The input lengths' vertex-scaling structure, for the intrinsic Delaunay Laplacian: the
  // problem's own when that is its scheme.
  auto vertex_scaling = [&] {
    if (s.scheme == Scheme::VertexScaling && s.geometry == Geometry::Euclidean) return s;
    StructureOptions vs;
    vs.scheme = Scheme::VertexScaling;
    return make_conformal_structure(t, problem.input_lengths, vs).structure;
  };
  Eigen::VectorXd lengths, hw, ew;
  edge_lengths(t, s, s.initial_u, lengths);
  if (!corner_angles(t, lengths, linear.angles).ok()) {
    throw InvalidInput(std::string(who) + ": the initial metric breaks a triangle inequality");
  }
  vertex_curvature(t, linear.angles, linear.curvature);
  if (scheme_traits(s.scheme).ptolemy_flips) {
    // The flow with flips linearises to the Laplacian of the intrinsic Delaunay triangulation.
    linear.L = intrinsic_delaunay_laplacian(t, problem.input_lengths, vertex_scaling());
  } else {
    halfedge_weights(t, s, s.initial_u, lengths, linear.angles, hw);
    edge_weights(t, hw, ew);
    linear.L = curvature_hessian(t, ew);
    if (!positive_definite_with_one_pin(linear.L)) {
      // Obtuse needles make some weights negative enough that L is indefinite (the repaired
      // Stanford dragon): the intrinsic Delaunay Laplacian has non-negative weights.
      linear.L = intrinsic_delaunay_laplacian(t, problem.input_lengths, vertex_scaling());
    }
  }
  // Area weights: a third of the 3D area of the faces around each vertex, normalised.
  linear.face_area = face_areas(*problem.mesh, t);
  linear.area = vertex_areas(t, linear.face_area);
  return linear;
}

parallel::Task<void> load_cholmod_beside(int rows, int row_nonzeros) {
  if (!SparseCholesky::automatic_takes_cholmod(rows,
                                               static_cast<Eigen::Index>(rows) * row_nonzeros) ||
      SparseCholesky::cholmod_loaded()) {
    return {};
  }
  return parallel::run_beside([] { SparseCholesky::cholmod_available(); });
}

}  // namespace cone_steps

ConeModel::ConeModel(std::unique_ptr<Data> data) : data_(std::move(data)) {}
ConeModel::ConeModel(ConeModel&&) noexcept = default;
ConeModel& ConeModel::operator=(ConeModel&&) noexcept = default;
ConeModel::~ConeModel() = default;

ConeModel build_cone_model(const FlowProblem& problem) {
  const build_counting::Scope counted(build_counting::Kind::ConeModel);
  auto data = std::make_unique<ConeModel::Data>();
  ConeModelData& model = *data;
  model.topology = &problem.topology;
  const Topology& t = problem.topology;
  if (t.components.size() != 1) {
    throw InvalidInput("select_cones: the mesh has " + std::to_string(t.components.size()) +
                       " connected components; choose cones for each on its own");
  }
  const int nv = model.nv = t.num_vertices;
  // (A mesh Laplacian: about 7 entries a row.)
  parallel::Task<void> loading = cone_steps::load_cholmod_beside(nv, 7);
  LinearFlow linear = linearise_flow(problem, "select_cones");
  const Eigen::SparseMatrix<double>& L = linear.L;
  model.angles = std::move(linear.angles);
  model.curvature = std::move(linear.curvature);
  model.face_area = std::move(linear.face_area);
  model.area = std::move(linear.area);
  model.vertex_faces = cone_steps::vertex_faces(t);
  model.neighbours = vertex_neighbours(t);
  const bool has_boundary = t.num_boundary_loops() > 0;
  model.chi = t.euler_characteristic();
  model.closed = !has_boundary;
  // Dirichlet vertices (the boundary) and the gauge of a closed surface are held at u = 0 by a
  // penalty on the diagonal; the cones are sources on the right-hand side, so one factorisation
  // serves every cone set.
  model.held.assign(nv, 0);
  for (int v = 0; v < nv; ++v) model.held[v] = has_boundary && t.is_boundary_vertex[v];
  if (model.closed) {
    model.gauge = 0;
    model.held[0] = 1;
  }
  const double penalty = kHeldPenalty * std::max(1.0, L.diagonal().cwiseAbs().maxCoeff());
  model.A = L;
  for (int v = 0; v < nv; ++v) {
    if (model.held[v]) model.A.coeffRef(v, v) += penalty;
  }
  model.cholesky.analyze(model.A);
  model.cholesky.factorize(model.A);
  model.rhs0 = -model.curvature;
  for (int v = 0; v < nv; ++v) {
    if (model.held[v] && v != model.gauge) model.rhs0[v] = 0;
  }
  model.angle_sum = Eigen::VectorXd::Zero(nv);
  model.largest_corner = Eigen::VectorXd::Zero(nv);
  for (int f = 0; f < t.num_faces; ++f) {
    for (int c = 0; c < 3; ++c) {
      const int v = t.triangles(f, c);
      model.angle_sum[v] += model.angles(f, c);
      model.largest_corner[v] = std::max(model.largest_corner[v], model.angles(f, c));
    }
  }
  return ConeModel(std::move(data));
}

using cone_steps::ConeSelector;
using cone_steps::SetFit;

ConeSelection select_cones(const Mesh& mesh, const ConeSelectionOptions& options) {
  check_cone_options(options);
  const FlowProblem problem = make_flow_problem(mesh, options.structure);
  return select_cones(build_cone_model(problem), options);
}

ConeSelection select_cones(const ConeModel& handle, const ConeSelectionOptions& options) {
  check_cone_options(options);
  const ConeModelData& model = handle.data();
  const Topology& t = *model.topology;
  ConeSelector selector = cone_steps::make_cone_selector(model, options);
  std::vector<int>& S = selector.S;
  if (model.closed && model.chi != 0) add_cone(selector, seed_cone(selector));

  ConeSelection result;
  SetFit fit = grow_cone_set(selector, result);
  Eigen::VectorXd k = fit.k;
  // Exchange: the greedy order is not the best placement of its cones (the first ones were
  // chosen when the others were missing).
  const int chosen = static_cast<int>(S.size());
  const int wanted = selector.wanted;
  if (result.within_bounds && chosen > 0 && chosen <= kExchangeCones &&
      (wanted < 0 || chosen == wanted) && fit.value < INFINITY) {
    exchange_cones(selector, fit);
    k = fit.k;
    result.area_energy = std::expm1(area_energy(t, model.face_area, fit.u, nullptr));
    result.log_scale_rms = std::sqrt(std::max(0.0, fit.u.dot(model.spread(fit.u))));
  }
  const cone_steps::LastGood& last_good = selector.last_good;
  if (!result.within_bounds && wanted < 0 && last_good.m > 0) {
    S.resize(static_cast<std::size_t>(last_good.m));
    if (selector.columns.size() > S.size()) selector.columns.resize(S.size());
    k = last_good.k;
    result.log_scale_rms = last_good.rms;
    result.within_bounds = true;
  }
  if (options.quantize && result.within_bounds && !S.empty()) {
    k = quantize_in_model(selector, S, k);
    const ConeObjective objective = cone_steps::cone_objective(selector, S);
    const Eigen::VectorXd u = objective.solve_u(k);
    result.area_energy = std::expm1(area_energy(t, model.face_area, u, nullptr));
    result.log_scale_rms = std::sqrt(std::max(0.0, u.dot(model.spread(u))));
  }
  result.vertices = std::move(S);
  result.linear_curvature.assign(k.data(), k.data() + k.size());
  return result;
}

double cone_lower_bound(const ConeModel& model, const ConeSelectionOptions& options, int v) {
  return cone_steps::cone_lower_bound(model.data(), options, v);
}

Eigen::VectorXd linearised_log_factors(const ConeModel& handle, const std::vector<Cone>& cones) {
  const ConeModelData& model = handle.data();
  Eigen::VectorXd rhs = model.rhs0;
  for (const Cone& c : cones) {
    if (c.vertex < 0 || c.vertex >= model.nv) {
      throw InvalidInput("linearised_log_factors: cone vertex " + std::to_string(c.vertex) +
                         " out of range (the model has " + std::to_string(model.nv) + " vertices)");
    }
    if (!model.held[c.vertex] || c.vertex == model.gauge) rhs[c.vertex] += c.curvature;
  }
  return linearised_inverse(handle, rhs);
}

Eigen::VectorXd linearised_inverse(const ConeModel& handle, const Eigen::VectorXd& r,
                                   bool approximately) {
  const ConeModelData& model = handle.data();
  if (r.size() != model.nv) {
    throw InvalidInput("linearised_inverse: " + std::to_string(r.size()) +
                       " values for a model of " + std::to_string(model.nv) + " vertices");
  }
  Eigen::VectorXd z =
      approximately ? model.cholesky.solve_approximately(r) : model.cholesky.solve(r);
  for (int v = 0; v < model.nv; ++v) {
    if (model.held[v]) z[v] = 0;  // (the penalty holds them at about 1e-10 of their neighbours)
  }
  return z;
}

namespace {

double log_scale_spread(const Topology& t, const std::vector<std::vector<int>>& neighbours,
                        const Eigen::VectorXd& area, const Eigen::VectorXd& u,
                        const std::vector<int>& cones) {
  const int nv = t.num_vertices;
  std::vector<int> ring(nv, kFarFromCones);
  for (int c : cones) grow_rings_within(neighbours, c, kSeparationRings, area, kRingArea, ring);
  double mean = 0, weight = 0;
  for (int v = 0; v < nv; ++v) {
    if (t.vertex_component[v] < 0) continue;
    mean += area[v] * u[v];
    weight += area[v];
  }
  mean /= std::max(weight, kSmallestWeight);
  double largest = 0;
  for (int v = 0; v < nv; ++v) {
    if (t.vertex_component[v] < 0 || ring[v] <= kSeparationRings) continue;
    largest = std::max(largest, std::abs(u[v] - mean));
  }
  return largest;
}

}  // namespace

double log_scale_spread(const Mesh& mesh, const Topology& t, const Eigen::VectorXd& u,
                        const std::vector<int>& cones) {
  return log_scale_spread(t, vertex_neighbours(t), vertex_areas(t, face_areas(mesh, t)), u, cones);
}

double log_scale_spread(const ConeModel& model, const Eigen::VectorXd& u,
                        const std::vector<int>& cones) {
  const ConeModelData& data = model.data();
  return log_scale_spread(*data.topology, data.neighbours, data.area, u, cones);
}

double area_distortion_of(const ConeModel& model, const Eigen::VectorXd& u) {
  const ConeModelData& data = model.data();
  if (u.size() != data.nv) {
    throw InvalidInput("area_distortion_of: " + std::to_string(u.size()) +
                       " values for a model of " + std::to_string(data.nv) + " vertices");
  }
  return std::expm1(cone_steps::area_energy(*data.topology, data.face_area, u, nullptr));
}

std::vector<Cone> quantize_cones(const std::vector<Cone>& cones, double total) {
  const double quarter = std::numbers::pi / 2;
  const long target_units = std::lround(total / quarter);
  std::vector<long> units(cones.size());
  long sum = 0;
  for (std::size_t i = 0; i < cones.size(); ++i) {
    units[i] = std::min(std::lround(cones[i].curvature / quarter), 3L);  // below 2 pi
    sum += units[i];
  }
  // Move the cones whose curvature lies closest to the other rounding, one quarter turn each.
  while (sum != target_units && !cones.empty()) {
    const long step = sum < target_units ? 1 : -1;
    std::size_t best = 0;
    double best_cost = INFINITY;
    for (std::size_t i = 0; i < cones.size(); ++i) {
      const double cost =
          std::abs(cones[i].curvature / quarter - static_cast<double>(units[i] + step));
      if (units[i] + step < 4 && cost < best_cost) {  // a cone stays below 2 pi
        best_cost = cost;
        best = i;
      }
    }
    if (!std::isfinite(best_cost)) break;
    units[best] += step;
    sum += step;
  }
  std::vector<Cone> out;
  for (std::size_t i = 0; i < cones.size(); ++i) {
    if (units[i] != 0) out.push_back({cones[i].vertex, static_cast<double>(units[i]) * quarter});
  }
  return out;
}

}  // namespace ricci
