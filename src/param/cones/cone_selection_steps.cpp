#include "param/cones/detail/cone_selection_steps.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "numerics/detail/parallel.hpp"
#include "param/cones/detail/cone_objective.hpp"
#include "ricci/errors.hpp"
#include "ricci/numerics/bounded_least_squares.hpp"

namespace ricci::cone_steps {
namespace {

/// Exchanges make two passes over the cones up to this many of them, one pass above (see
/// kExchangeCones in cones.cpp).
constexpr int kExchangeTwice = 8;

/// Most doubles the selection keeps as columns of A^-1 (#V per cone): 320 MB.
constexpr double kColumnValues = 4e7;
/// Cone sets of at most this many cones keep their columns' face means too: an evaluation on the
/// faces streams 2 #F #S values and gathers nothing, one through u streams 2 #V #S and gathers
/// over the faces twice, so the faces win while #S is small (wall time of whole runs, faces
/// against vertices: 0.94-0.99 at 4 and 8 cones on kitten, face, bunny, camelhead; 1.08 on face
/// with 16).
constexpr int kFaceColumnCones = 8;

/// Without a cap (options.max_cones 0) automatic selection also stops when doubling the cones
/// no longer lowers the log scale bound's measure by this factor, once it has at least
/// kStallCheckFrom of them (6 |chi| on a closed surface of chi < 0, whose curvature needs about
/// that many cones within their bounds: each takes at most about pi on a valence-6 vertex):
/// more cones would buy nothing (a CAD part's needles, whose spread no cone set removes).
constexpr double kStallFactor = 0.95;
constexpr int kStallCheckFrom = 64;
/// The greedy adds max(1, #S / kBatchDivisor) cones a step (one fit per batch, not per cone).
constexpr int kBatchDivisor = 8;

/// The fits' stopping rule (ConeObjective::relative_decrease). With a count of cones only the
/// fits' curvatures matter, and 1e-8 took the last two or three iterations of most fits for no
/// change a map shows (the 48 reference rows: E within 1e-4 relative, angle distortion within
/// 1e-4; choosing the cones 5-12 % faster). The automatic count stops on the log scale's spread
/// from one fit to the next (spread_stalled), which the looser fits moved: the corpus's armadillo
/// stopped at 128 cones instead of 144 (E 0.086 -> 0.107), so it keeps 1e-8.
constexpr double kCountedRelativeDecrease = 1e-6;
constexpr double kAutomaticRelativeDecrease = 1e-8;
/// Curvature sums (radians) meet 2 pi chi within this, relative to 1 + |2 pi chi|; a lower
/// bound sum may exceed 2 pi chi by this (absolute): rounding of a sum of a few dozen
/// curvatures of order pi, far below any cone that matters.
constexpr double kCurvatureSumSlack = 1e-9;
/// A curvature within this of its bound counts as at the bound (not free) when the sum
/// constraint's multiplier is estimated from the free cones.
constexpr double kAtBound = 1e-9;
/// An exchange is kept when it lowers the objective by more than this, relative to 1 + |F|:
/// a smaller gain is rounding, and the exchange would only move cones around.
constexpr double kExchangeGain = 1e-9;
/// Quarter-turn curvatures may exceed their bounds by this: k pi / 2 against a bound that is
/// itself a multiple of pi / 2 (2 pi - 3 pi / 2) differs by rounding only.
constexpr double kQuarterTurnSlack = 1e-12;
/// A quarter-turn move is kept when it lowers the objective by more than this, relative to
/// 1 + |F| (a smaller gain is rounding).
constexpr double kQuantizeGain = 1e-12;
/// Quarter-turn moves tried per round, best predicted first.
constexpr std::size_t kMovesTried = 8;

/// Lowers hops[v] to the number of edges from `source` to v, for every v within max_rings edges
/// of it (breadth-first over the vertex neighbour lists).
void grow_rings(const std::vector<std::vector<int>>& neighbours, int source, int max_rings,
                std::vector<int>& hops) {
  std::vector<int> frontier = {source};
  hops[source] = 0;
  for (int r = 1; r <= max_rings && !frontier.empty(); ++r) {
    std::vector<int> next;
    for (int a : frontier) {
      for (int b : neighbours[a]) {
        if (hops[b] > r) {
          hops[b] = r;
          next.push_back(b);
        }
      }
    }
    frontier = std::move(next);
  }
}

}  // namespace

/// Each vertex's neighbours along the edges, in edge order.
std::vector<std::vector<int>> vertex_neighbours(const Topology& t) {
  std::vector<std::vector<int>> neighbours(t.num_vertices);
  for (int e = 0; e < t.num_edges; ++e) {
    neighbours[t.edge_vertices(e, 0)].push_back(t.edge_vertices(e, 1));
    neighbours[t.edge_vertices(e, 1)].push_back(t.edge_vertices(e, 0));
  }
  return neighbours;
}

/// Cone bounds: drawable on the input's faces, and a positive angle. Near a cone the map scales
/// the angles at the vertex by about (its cone angle) / (its angle sum in the input), so the
/// largest input corner there, scaled, must stay below max_corner_angle; and the average below
/// max_face_angle.
double cone_lower_bound(const ConeModelData& model, const ConeSelectionOptions& options, int v) {
  const double by_average = options.max_face_angle * model.topology->vertex_degree[v];
  const double by_largest = options.max_corner_angle * model.angle_sum[v] / model.largest_corner[v];
  return 2 * std::numbers::pi - std::min(by_average, by_largest);
}

ConeSelector make_cone_selector(const ConeModelData& model, const ConeSelectionOptions& options) {
  const Topology& t = *model.topology;
  const int nv = model.nv;
  ConeSelector selector(model, options);
  selector.u0 = model.cholesky.solve(model.rhs0);
  selector.Pu0 = model.spread(selector.u0);
  selector.u0_faces = face_means(t, selector.u0);
  selector.u0_rhs0 = selector.u0.dot(model.rhs0);
  selector.upper = options.max_curvature;
  selector.separation = kSeparationRings;
  selector.ring.assign(nv, kFarFromCones);
  selector.M.resize(0, 0);
  selector.green.resize(0, 0);
  selector.smooth = options.smoothness / t.num_faces;
  selector.r.resize(0);
  selector.is_cone.assign(nv, 0);
  // No cap unless one is asked for: a count places that many cones, the automatic count stops
  // at the bound (or when more cones stop helping, see kStallFactor).
  selector.max_cones = options.max_cones > 0 ? options.max_cones : nv;
  selector.wanted = options.count > 0 ? std::min(options.count, selector.max_cones) : -1;
  selector.total = 2 * std::numbers::pi * model.chi;
  selector.on_sliver.assign(nv, 0);
  for (int f = 0; f < t.num_faces; ++f) {
    if (model.angles.row(f).maxCoeff() <= options.max_corner_angle) continue;
    for (int c = 0; c < 3; ++c) selector.on_sliver[t.triangles(f, c)] = 1;
  }
  return selector;
}

ConeObjective cone_objective(const ConeSelector& selector, const std::vector<int>& cones) {
  const ConeSelector& s = selector;
  const ConeModelData& model = s.model;
  ConeObjective objective{model.cholesky, model.rhs0, s.u0,     *model.topology,    model.face_area,
                          cones,          s.columns,  s.smooth, &model.vertex_faces};
  objective.u0_faces = &s.u0_faces;
  objective.u0_rhs0 = s.u0_rhs0;
  if (&cones == &s.S) objective.green = &s.green;
  objective.relative_decrease =
      s.wanted >= 0 ? kCountedRelativeDecrease : kAutomaticRelativeDecrease;
  return objective;
}

void add_cone(ConeSelector& selector, int v) {
  ConeSelector& s = selector;
  const ConeModelData& model = s.model;
  const int nv = model.nv;
  const int m = static_cast<int>(s.S.size());
  Eigen::VectorXd e = Eigen::VectorXd::Zero(nv);
  e[v] = 1;
  Eigen::VectorXd g = model.cholesky.solve(e);
  const Eigen::VectorXd Pg = model.spread(g);
  const bool keep = static_cast<double>(nv) * (m + 1) <= kColumnValues &&
                    s.columns.size() == static_cast<std::size_t>(m);
  const int nf = model.topology->num_faces;
  const bool keep_faces =
      keep && m + 1 <= kFaceColumnCones && static_cast<double>(nv + nf) * (m + 1) <= kColumnValues;
  s.M.conservativeResize(m + 1, m + 1);
  s.green.conservativeResize(m + 1, m + 1);
  s.r.conservativeResize(m + 1);
  if (keep) {
    // M_im = g_i^T P g_m (= (A^-1 P g_m)_{S_i}: A is symmetric).
    for (int i = 0; i < m; ++i) s.M(i, m) = s.M(m, i) = s.columns[i]->g.dot(Pg);
    s.M(m, m) = g.dot(Pg);
  } else {
    s.columns.clear();
    const Eigen::VectorXd h = model.cholesky.solve(Pg);
    for (int i = 0; i < m; ++i) s.M(i, m) = s.M(m, i) = h[s.S[i]];
    s.M(m, m) = h[v];
  }
  s.S.push_back(v);
  s.is_cone[v] = 1;
  for (int i = 0; i <= m; ++i) s.green(i, m) = s.green(m, i) = g[s.S[i]];
  s.r[m] = g.dot(s.Pu0);
  if (keep) {
    auto column = std::make_shared<ConeColumn>();
    if (keep_faces) column->faces = face_means(*model.topology, g);
    column->rhs0_dot = g.dot(model.rhs0);
    column->g = std::move(g);
    s.columns.push_back(std::move(column));
  }
  grow_rings(s.model.neighbours, v, s.separation, s.ring);
}

void reset_rings(ConeSelector& selector) {
  std::fill(selector.ring.begin(), selector.ring.end(), kFarFromCones);
  for (int v : selector.S)
    grow_rings(selector.model.neighbours, v, selector.separation, selector.ring);
}

std::vector<int> first_cone_candidates(const ConeSelector& selector) {
  const ConeModelData& model = selector.model;
  const int nv = model.nv, chi = model.chi, gauge = model.gauge;
  const Eigen::VectorXd& curvature = model.curvature;
  int first = 1 % nv;
  for (int v = 0; v < nv; ++v) {
    if (v == gauge) continue;
    if ((chi > 0 && curvature[v] > curvature[first]) ||
        (chi < 0 && curvature[v] < curvature[first])) {
      first = v;
    }
  }
  std::vector<int> candidates = {first};
  std::vector<int> hops(nv, std::numeric_limits<int>::max());
  grow_rings(selector.model.neighbours, first, std::numeric_limits<int>::max(), hops);
  while (static_cast<int>(candidates.size()) <
         std::max(1, selector.options.try_first_cone_candidates)) {
    int far = -1;
    for (int v = 0; v < nv; ++v) {
      if (v != gauge && (far < 0 || hops[v] > hops[far])) far = v;
    }
    if (far < 0 || hops[far] == 0) break;
    candidates.push_back(far);
    grow_rings(selector.model.neighbours, far, std::numeric_limits<int>::max(), hops);
  }
  return candidates;
}

int seed_cone(const ConeSelector& selector) {
  const ConeModelData& model = selector.model;
  const std::vector<int> candidates = first_cone_candidates(selector);
  const int n = static_cast<int>(candidates.size());
  // One solve for all candidates (a block of right-hand sides).
  Eigen::MatrixXd rhs = model.rhs0.replicate(1, n);
  for (int j = 0; j < n; ++j) rhs(candidates[j], j) += selector.total;
  const Eigen::MatrixXd u = model.cholesky.solve_columns(rhs);
  int best = candidates.front();
  double best_energy = INFINITY;
  for (int j = 0; j < n; ++j) {
    const double energy = u.col(j).dot(model.spread(u.col(j)));
    if (energy < best_energy) {
      best_energy = energy;
      best = candidates[j];
    }
  }
  return best;
}

SetFit fit_cone_set(ConeSelector& selector, const Eigen::VectorXd* start, bool need_q) {
  ConeSelector& s = selector;
  const ConeModelData& model = s.model;
  const std::vector<int>& S = s.S;
  const int m = static_cast<int>(S.size());
  SetFit fit;
  Eigen::VectorXd lo(m), hi(m);
  for (int i = 0; i < m; ++i) {
    lo[i] = cone_lower_bound(model, s.options, S[i]);
    hi[i] = s.upper;
  }
  if (m > 0) {
    BoundedLeastSquaresOptions sum;
    sum.sum_constraint = model.closed;
    sum.total = s.total;
    BoundedLeastSquaresResult l2 = bounded_least_squares(s.M, s.r, lo, hi, sum);
    fit.within = l2.feasible;
    fit.k = std::move(l2.x);
    fit.lambda = l2.multiplier;
  }
  if (m > 0 && fit.within) {
    // From the L2 minimiser to the area distortion's: the gradient of F at it chooses the next
    // cone, so the greedy measures what the texture shows. A start within the bounds (the
    // previous step's minimiser) saves most iterations; `hessian` holds the previous estimate.
    const ConeObjective objective = cone_objective(s, S);
    if (start && start->size() == m) {
      bool inside =
          std::abs(start->sum() - fit.k.sum()) <= kCurvatureSumSlack * (1 + std::abs(s.total));
      for (int i = 0; i < m; ++i) {
        inside = inside && (*start)[i] >= lo[i] && (*start)[i] <= hi[i];
      }
      if (inside) fit.k = *start;
    }
    fit.u = minimise_cone_objective(objective, s.M, s.green, lo, hi, model.closed, s.total, fit.k,
                                    s.hessian, need_q ? &fit.q : nullptr, fit.value);
    fit.lambda = 0;
    if (model.closed && need_q) {
      int free = 0;
      for (int i = 0; i < m; ++i) {
        if (fit.k[i] > lo[i] + kAtBound && fit.k[i] < hi[i] - kAtBound) {
          fit.lambda -= fit.q[S[i]];
          ++free;
        }
      }
      fit.lambda /= std::max(free, 1);
    }
  } else {
    Eigen::VectorXd rhs = model.rhs0;
    for (int i = 0; i < m; ++i) rhs[S[i]] += fit.k[i];
    fit.u = model.cholesky.solve(rhs);
    fit.q = model.cholesky.solve(model.spread(fit.u));
  }
  return fit;
}

namespace {

/// Whether v may take a new cone: not held, not a cone, in the mesh, outside the cones' rings,
/// and (on pass 0) not on a sliver.
bool open_for_cone(const ConeSelector& s, int v, int pass) {
  if (s.model.held[v] || s.is_cone[v] || s.model.topology->vertex_component[v] < 0 ||
      s.ring[v] <= s.separation) {
    return false;
  }
  return !(pass == 0 && s.on_sliver[v]);
}

/// The sum of the cones' lower bounds.
double lower_bound_sum(const ConeSelector& s) {
  double lower_sum = 0;
  for (int c : s.S) lower_sum += cone_lower_bound(s.model, s.options, c);
  return lower_sum;
}

}  // namespace

int best_candidate(const ConeSelector& selector, const SetFit& fit) {
  const ConeSelector& s = selector;
  const double lower_sum = lower_bound_sum(s);
  int best = -1;
  for (int pass = 0; pass < 2 && best < 0; ++pass) {
    double best_gain = -1;
    for (int v = 0; v < s.model.nv; ++v) {
      if (!open_for_cone(s, v, pass)) continue;
      const double gain = std::abs(fit.q[v] + fit.lambda);
      if (gain <= best_gain) continue;
      const double lo_v = cone_lower_bound(s.model, s.options, v);
      if (s.model.closed && lo_v > 0 && lower_sum + lo_v > s.total + kCurvatureSumSlack) continue;
      best = v;
      best_gain = gain;
    }
  }
  return best;
}

bool add_cones(ConeSelector& selector, const SetFit& fit) {
  ConeSelector& s = selector;
  const int m = static_cast<int>(s.S.size());
  // dF/dk_t (or dJ/dk_t) for every vertex t at once: q = A^-1 dF/du (A is symmetric); on a
  // closed surface a new cone's curvature comes out of the others', whose common gradient is
  // -lambda.
  const int batch = std::max(1, m / kBatchDivisor);
  const int room = (s.wanted >= 0 ? s.wanted : s.max_cones) - m;
  std::vector<std::pair<double, int>> order;
  for (int pass = 0; pass < 2 && order.empty(); ++pass) {
    for (int v = 0; v < s.model.nv; ++v) {
      if (open_for_cone(s, v, pass)) order.emplace_back(-std::abs(fit.q[v] + fit.lambda), v);
    }
  }
  if (order.empty()) {
    if (s.separation == 0) return false;
    --s.separation;  // crowded (high genus on a coarse mesh): let cones come closer
    reset_rings(s);
    return true;
  }
  std::sort(order.begin(), order.end());
  // On a closed surface the cones' curvatures sum to 2 pi chi, so their lower bounds must not
  // exceed it: a vertex with a corner near pi (a CAD sliver) must take a strong positive cone,
  // and a few of them made the bounds infeasible (unbounded curvatures of 3 pi on a needle
  // cylinder). Candidates with a positive lower bound are skipped once they would.
  double lower_sum = lower_bound_sum(s);
  int added = 0;
  for (const auto& [gain, v] : order) {
    if (added >= std::min(batch, room)) break;
    if (s.ring[v] <= s.separation) continue;  // next to a cone added in this batch
    const double lo_v = cone_lower_bound(s.model, s.options, v);
    if (s.model.closed && lo_v > 0 && lower_sum + lo_v > s.total + kCurvatureSumSlack) continue;
    add_cone(s, v);
    lower_sum += lo_v;
    ++added;
  }
  return added != 0;  // none: no candidate keeps the bounds feasible
}

namespace {

/// Records a greedy step's fit in result (in bounds, area energy, the log scale's spread
/// outside the rings and its rms) and in last_good; returns the spread.
double record_fit(ConeSelector& s, const SetFit& fit, ConeSelection& result) {
  const ConeModelData& model = s.model;
  const int m = static_cast<int>(s.S.size());
  result.within_bounds = fit.within;
  const Eigen::VectorXd& u = fit.u;
  if (m > 0 && fit.within) {
    result.area_energy = std::expm1(area_energy(*model.topology, model.face_area, u, nullptr));
  }
  const Eigen::VectorXd Pu = model.spread(u);
  const double mean = model.area.dot(u);
  double largest = 0;
  for (int v = 0; v < model.nv; ++v) {
    if (s.ring[v] > s.separation) largest = std::max(largest, std::abs(u[v] - mean));
  }
  result.max_log_scale.push_back(largest);
  result.log_scale_rms = std::sqrt(std::max(0.0, u.dot(Pu)));
  if (result.within_bounds && m > 0) {
    s.last_good = {m, fit.k, result.log_scale_rms};
  }
  return largest;
}

/// Automatic count without a cap: more cones stopped helping (spread_stalled).
bool stalled(const ConeSelector& s) {
  if (s.options.max_cones > 0) return false;
  return spread_stalled(s.spread_history, stall_check_from(s.model.closed, s.model.chi));
}

}  // namespace

int stall_check_from(bool closed, int chi) {
  return closed && chi < 0 ? std::max(kStallCheckFrom, 6 * -chi) : kStallCheckFrom;
}

bool spread_stalled(const std::vector<std::pair<int, double>>& history, int from) {
  if (history.empty()) return false;
  const auto [m, now] = history.back();
  if (m < from) return false;
  for (auto it = history.rbegin(); it != history.rend(); ++it) {
    if (2 * it->first <= m) return now > kStallFactor * it->second;
  }
  return false;
}

SetFit grow_cone_set(ConeSelector& selector, ConeSelection& result) {
  ConeSelector& s = selector;
  SetFit fit;
  for (;;) {
    const int m = static_cast<int>(s.S.size());
    Eigen::VectorXd warm;
    if (fit.k.size() > 0 && fit.k.size() < m && fit.within) {
      warm = Eigen::VectorXd::Zero(m);  // the new cones at 0
      warm.head(fit.k.size()) = fit.k;
    }
    fit = fit_cone_set(s, &warm, true);
    const double largest = record_fit(s, fit, result);
    s.spread_history.emplace_back(m, largest);
    const bool done = s.wanted >= 0
                          ? m >= s.wanted
                          : (largest <= s.options.max_log_scale && result.within_bounds) ||
                                m >= s.max_cones || stalled(s);
    if (done || !add_cones(s, fit)) break;
  }
  return fit;
}

namespace {

/// Removes row and column i of the square X.
void erase_row_and_column(Eigen::MatrixXd& X, int i) {
  const int n = static_cast<int>(X.rows());
  Eigen::MatrixXd Y(n - 1, n - 1);
  for (int a = 0, ya = 0; a < n; ++a) {
    if (a == i) continue;
    for (int b = 0, yb = 0; b < n; ++b) {
      if (b == i) continue;
      Y(ya, yb++) = X(a, b);
    }
    ++ya;
  }
  X = std::move(Y);
}

/// What an exchange restores when it is not kept.
struct ConeSetBackup {
  std::vector<int> S;
  Eigen::MatrixXd M, green, hessian;
  Eigen::VectorXd r;
  std::vector<int> ring;
  int removed = -1;
  bool had_columns = false;
  SharedColumn removed_column;
};

/// Takes cone i out of the set (its rows of M, green, r, the Hessian and its column); returns
/// what restore_cone_set puts back.
ConeSetBackup take_out_cone(ConeSelector& s, int i) {
  ConeSetBackup before;
  before.S = s.S;
  before.M = s.M;
  before.green = s.green;
  before.r = s.r;
  before.ring = s.ring;
  before.removed = s.S[i];
  before.had_columns = s.columns.size() == s.S.size();
  if (before.had_columns) before.removed_column = std::move(s.columns[i]);
  erase_row_and_column(s.M, i);
  erase_row_and_column(s.green, i);
  Eigen::VectorXd r_less(s.r.size() - 1);
  for (int a = 0, ya = 0; a < s.r.size(); ++a) {
    if (a != i) r_less[ya++] = s.r[a];
  }
  s.r = std::move(r_less);
  s.S.erase(s.S.begin() + i);
  if (before.had_columns) s.columns.erase(s.columns.begin() + i);
  s.is_cone[before.removed] = 0;
  reset_rings(s);
  before.hessian = s.hessian;
  if (s.hessian.rows() == static_cast<int>(before.S.size())) {
    erase_row_and_column(s.hessian, i);  // a principal submatrix: still positive definite
  } else {
    s.hessian.resize(0, 0);
  }
  return before;
}

/// Puts cone i back where take_out_cone found it (a candidate added since at the end dropped).
void restore_cone_set(ConeSelector& s, ConeSetBackup&& before, int i) {
  if (before.had_columns) {
    if (s.columns.size() > before.S.size() - 1) s.columns.pop_back();
    s.columns.insert(s.columns.begin() + i, std::move(before.removed_column));
  } else {
    s.columns.clear();
  }
  s.S = before.S;
  s.M = before.M;
  s.green = before.green;
  s.r = before.r;
  s.ring = before.ring;
  s.hessian = before.hessian;
  s.is_cone[before.removed] = 1;
}

/// The first half of exchange i: the fit of the other cones (s.S without cone i, which
/// take_out_cone removed) and the quasi-Newton Hessian it left.
struct WithoutCone {
  SetFit without;
  Eigen::MatrixXd hessian;
};

/// Fits the cones left after taking out cone i of the set whose curvatures were k, starting from
/// cone i's curvature shared by the others (the sum is kept).
WithoutCone fit_without_cone(ConeSelector& s, const Eigen::VectorXd& k, int i) {
  Eigen::VectorXd start(s.S.size());
  for (int a = 0, ya = 0; a < k.size(); ++a) {
    if (a != i) start[ya++] = k[a] + k[i] / static_cast<double>(s.S.size());
  }
  WithoutCone result;
  result.without = fit_cone_set(s, &start, true);
  result.hessian = s.hessian;
  return result;
}

/// Cone i taken out and the best candidate for the others put in; kept (fit becomes the new
/// set's, the new cone at the end of S) when the objective falls. Returns whether it was kept.
/// `ahead` (when valid): the first half of this exchange, computed beside the one before on a
/// copy of the state this exchange starts from. `next` gets the first half of exchange i + 1 on
/// this state (what that exchange starts from when this one is not kept), computed beside.
bool exchange_cone(ConeSelector& s, SetFit& fit, int i, parallel::Task<WithoutCone>& ahead,
                   parallel::Task<WithoutCone>& next) {
  if (i + 1 < static_cast<int>(s.S.size())) {
    next = parallel::run_beside([copy = s, k = fit.k, i]() mutable {
      take_out_cone(copy, i + 1);
      return fit_without_cone(copy, k, i + 1);
    });
  }
  ConeSetBackup before = take_out_cone(s, i);
  WithoutCone half;
  if (ahead.valid()) {
    half = ahead.get();
    s.hessian = half.hessian;
  } else {
    half = fit_without_cone(s, fit.k, i);
  }
  const SetFit& without = half.without;
  const int v = without.within ? best_candidate(s, without) : -1;
  if (v >= 0 && v != before.removed) {
    add_cone(s, v);
    Eigen::VectorXd extended = Eigen::VectorXd::Zero(static_cast<int>(s.S.size()));
    extended.head(without.k.size()) = without.k;
    const SetFit with = fit_cone_set(s, &extended, false);
    if (with.within && with.value < fit.value - kExchangeGain * (1 + std::abs(fit.value))) {
      fit = with;
      return true;
    }
    s.is_cone[v] = 0;
  }
  restore_cone_set(s, std::move(before), i);
  return false;
}

}  // namespace

bool exchange_cones(ConeSelector& selector, SetFit& fit) {
  const int chosen = static_cast<int>(selector.S.size());
  const int passes = chosen <= kExchangeTwice ? 2 : 1;
  bool any = false;
  for (int pass = 0; pass < passes; ++pass) {
    bool improved = false;
    // Each exchange's first half is fitted beside the exchange before it, on the state that one
    // leaves when it is not kept (most are not); kept, the look-ahead is dropped. The same
    // exchanges, in the same order, as one after the other.
    parallel::Task<WithoutCone> ahead;
    for (int i = 0; i < static_cast<int>(selector.S.size()); ++i) {
      parallel::Task<WithoutCone> next;
      if (exchange_cone(selector, fit, i, ahead, next)) {
        improved = true;
        next = {};  // (waits for the look-ahead: it read the state before this exchange)
      }
      ahead = std::move(next);
    }
    any = any || improved;
    if (!improved) break;
  }
  return any;
}

Eigen::VectorXd quantize_in_model(const ConeSelector& selector, const std::vector<int>& cones,
                                  const Eigen::VectorXd& k_real) {
  const ConeSelector& s = selector;
  const ConeModelData& model = s.model;
  const int m = static_cast<int>(cones.size());
  const double quarter = std::numbers::pi / 2;
  std::vector<Cone> real(m);
  double sum = 0;
  for (int i = 0; i < m; ++i) {
    real[i] = {i, k_real[i]};
    sum += k_real[i];
  }
  const double units_total = std::round((model.closed ? s.total : sum) / quarter) * quarter;
  Eigen::VectorXd kq = Eigen::VectorXd::Zero(m);
  for (const Cone& c : quantize_cones(real, units_total)) kq[c.vertex] = c.curvature;
  auto allowed = [&](int i, double value) {
    return value <= s.options.max_curvature + kQuarterTurnSlack &&
           value >= cone_lower_bound(model, s.options, cones[i]) - kQuarterTurnSlack;
  };
  const ConeObjective objective = cone_objective(s, cones);
  Eigen::VectorXd u = objective.solve_u(kq);
  double value = objective.value(u, kq);
  for (int move = 0; move < 4 * m + 8; ++move) {
    const Eigen::VectorXd g = objective.gradient(u);
    std::vector<std::pair<double, std::pair<int, int>>> moves;  // predicted change, (to, from)
    for (int i = 0; i < m; ++i) {
      for (int j = 0; j < m; ++j) {
        if (i == j || !allowed(i, kq[i] + quarter) || !allowed(j, kq[j] - quarter)) continue;
        moves.push_back({quarter * (g[i] - g[j]), {i, j}});
      }
    }
    std::sort(moves.begin(), moves.end());
    bool improved = false;
    for (std::size_t a = 0; a < std::min<std::size_t>(moves.size(), kMovesTried) && !improved;
         ++a) {
      const auto [i, j] = moves[a].second;
      Eigen::VectorXd trial = kq;
      trial[i] += quarter;
      trial[j] -= quarter;
      const Eigen::VectorXd u_trial = objective.solve_u(trial);
      const double v = objective.value(u_trial, trial);
      if (v < value - kQuantizeGain * (1 + std::abs(value))) {
        kq = trial;
        u = u_trial;
        value = v;
        improved = true;
      }
    }
    if (!improved) break;
  }
  return kq;
}

}  // namespace ricci::cone_steps
