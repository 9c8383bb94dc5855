#include "ricci/param/cones/free_seams.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "numerics/detail/parallel.hpp"
#include "numerics/detail/weighted_square.hpp"
#include "param/cones/detail/cone_selection_steps.hpp"
#include "param/cones/detail/linear_flow.hpp"
#include "ricci/errors.hpp"
#include "ricci/numerics/sparse_cholesky.hpp"
#include "ricci/numerics/timer.hpp"

namespace ricci {

namespace {

/// Vertices of the cut's edges, and those the prescribed target leaves free (a free boundary).
std::vector<char> free_vertices(const Topology& t, const CutGraph& cut, const Target& prescribed) {
  std::vector<char> free = cut_vertices(t, cut);
  // The cones are free whether or not a cut edge reaches them (one cone on a sphere has none).
  for (int v : cut.nodes) free[v] = 1;
  for (int v = 0; v < t.num_vertices; ++v) free[v] = free[v] || prescribed.fixed[v];
  return free;
}

/// Prescribed where prescribed, the linearised flow's curvature where free, its sum made
/// exactly 2 pi chi (what L u adds sums to 0 up to rounding; the residual goes to the free
/// vertices in proportion to their area).
void fill_target(const cone_steps::LinearFlow& linear, const Topology& t, FreeSeamTarget& result,
                 const Target& prescribed, const Eigen::VectorXd& curvature) {
  const int nv = t.num_vertices;
  result.target.curvature = prescribed.curvature;
  result.target.fixed.assign(nv, 0);
  double free_area = 0, residual = 0;
  for (int v = 0; v < nv; ++v) {
    if (!result.free[v] || t.vertex_component[v] < 0) continue;
    result.target.curvature[v] = curvature[v];
    free_area += linear.area[v];
  }
  for (int v = 0; v < nv; ++v) {
    if (t.vertex_component[v] >= 0) residual += result.target.curvature[v] - linear.curvature[v];
  }
  for (int v = 0; v < nv && free_area > 0; ++v) {
    if (result.free[v] && t.vertex_component[v] >= 0)
      result.target.curvature[v] -= residual * linear.area[v] / free_area;
  }
  // Curvature above kMaxFreeCurvature held there, its excess spread over the other free vertices
  // by area (which may push some of them over in turn: a few passes, as water fills). The sum
  // stays 2 pi chi. (A generated cylinder with 0.1-degree needles asked for 10.7 at a vertex.)
  std::vector<char> capped(static_cast<std::size_t>(nv), 0);
  for (int pass = 0; pass < 16; ++pass) {
    double excess = 0, open_area = 0;
    for (int v = 0; v < nv; ++v) {
      if (!result.free[v] || t.vertex_component[v] < 0) continue;
      if (result.target.curvature[v] > kMaxFreeCurvature) {
        excess += result.target.curvature[v] - kMaxFreeCurvature;
        result.target.curvature[v] = kMaxFreeCurvature;
        capped[static_cast<std::size_t>(v)] = 1;
      } else if (!capped[static_cast<std::size_t>(v)]) {
        open_area += linear.area[v];
      }
    }
    if (excess == 0 || !(open_area > 0)) break;
    for (int v = 0; v < nv; ++v) {
      if (result.free[v] && t.vertex_component[v] >= 0 && !capped[static_cast<std::size_t>(v)])
        result.target.curvature[v] += excess * linear.area[v] / open_area;
    }
  }
  result.capped_vertices = static_cast<int>(std::count(capped.begin(), capped.end(), 1));
  result.target.description = "flat off the cut, " + std::to_string(result.free_vertices) +
                              " seam and boundary vertices at their least distorting curvature";
}

/// E (eq. 9) of the linearised metric, faces scaled by e^{2 u_f}, u_f their corners' mean.
double seam_area_energy(const cone_steps::LinearFlow& linear, const Topology& t,
                        const Eigen::VectorXd& u) {
  double z = 0, e = 0;
  Eigen::VectorXd scale(t.num_faces);
  for (int f = 0; f < t.num_faces; ++f) {
    const double uf = (u[t.triangles(f, 0)] + u[t.triangles(f, 1)] + u[t.triangles(f, 2)]) / 3;
    scale[f] = std::exp(2 * uf);
    z += linear.face_area[f] * scale[f];
  }
  for (int f = 0; f < t.num_faces; ++f) {
    const double r = scale[f] / z - 1;
    e += linear.face_area[f] * r * r;
  }
  return e;
}

/// The free seams' problem on one mesh, analysed once: the minimiser of
///     4 u^T M u + beta sum_{v free} k_v^2   subject to   L u = k - K,
/// k the target curvature (given on the prescribed vertices, free on the others). Its
/// stationarity gives u = -M^-1 L lambda / 8 and k_v = lambda_v / (2 beta) on the free vertices,
/// and the multipliers solve the sparse positive definite system
///     (L M^-1 L / 8 + diag(free) / (2 beta)) lambda = K - (k on the prescribed rows, 0 else),
/// whose pattern does not depend on which vertices are free: one symbolic analysis serves every
/// cut the cone selection tries, and the final Dirichlet system (its pattern is within this one).
/// Two factorisations share that pattern, so that two cuts can be solved side by side (the two
/// candidate roots), and the second is left for the Dirichlet system.
class SeamSystem {
 public:
  SeamSystem(const cone_steps::LinearFlow& linear, const Topology& t, double smoothness)
      : linear_(linear), t_(t) {
    const int nv = t.num_vertices;
    // A vertex of no face has an empty row of L: its area floor keeps M invertible. (The
    // pattern holds the whole diagonal, whatever is free.)
    Eigen::VectorXd weight(nv);
    for (int v = 0; v < nv; ++v) weight[v] = 1.0 / (8 * std::max(linear.area[v], 1e-300));
    base_ = numerics_detail::square_pattern(linear.L);
    numerics_detail::set_weighted_square(linear.L, weight, base_);
    beta_ = smoothness / std::max(1, t.num_faces);
    // Both analyses at once: without a free helper the second runs after the first, and it would
    // have been the Dirichlet system's own analysis anyway.
    parallel::run_pair([&] { factors_[0].analyze(base_); }, [&] { factors_[1].analyze(base_); });
  }

  /// The pattern every system of this mesh is factorised in (explicit zeros included).
  const Eigen::SparseMatrix<double>& pattern() const { return base_; }
  /// Factorisation `which` (0 or 1), for a system other than solve()'s (the Dirichlet one): it
  /// no longer holds a free set's.
  SparseCholesky& take_factor(int which) {
    held_.at(static_cast<std::size_t>(which)).clear();
    return factors_.at(static_cast<std::size_t>(which));
  }

  /// The target for these free vertices; `multiplier` (optional) gets lambda on the prescribed
  /// vertices (how much freeing each would lower the objective, to first order), 0 elsewhere.
  /// Uses factorisation `which`: calls with different ones may run at once. When it holds the
  /// system of another free set, the rounds' usual case (a cone's path to the cut freed, a few
  /// vertices of the cut moved), that factor is modified (SparseCholesky::update_diagonal)
  /// instead of factorised afresh.
  FreeSeamTarget solve(std::vector<char> free, const Target& prescribed,
                       Eigen::VectorXd* multiplier, int which = 0) {
    const auto start = Clock::now();
    const int nv = t_.num_vertices;
    FreeSeamTarget result;
    result.free = std::move(free);
    Eigen::VectorXd rhs = linear_.curvature;
    // A free vertex's curvature costs beta k^2; beta = 0 (no smoothing) is approached.
    const double weight = 1.0 / (2 * std::max(beta_, 1e-12));
    for (int v = 0; v < nv; ++v) {
      if (t_.vertex_component[v] < 0) {
        rhs[v] = 0;  // a vertex of no face: lambda = 0
      } else if (result.free[v]) {
        ++result.free_vertices;
      } else {
        rhs[v] -= prescribed.curvature[v];
      }
    }
    SparseCholesky& cholesky = factors_.at(static_cast<std::size_t>(which));
    std::vector<char>& held = held_.at(static_cast<std::size_t>(which));
    if (!update_held(held, result.free, weight, cholesky)) {
      Eigen::SparseMatrix<double> system = base_;
      for (int v = 0; v < nv; ++v) {
        if (t_.vertex_component[v] < 0) {
          system.coeffRef(v, v) += 1;
        } else if (result.free[v]) {
          system.coeffRef(v, v) += weight;
        }
      }
      held.clear();
      cholesky.factorize(system);
    }
    held = result.free;
    const Eigen::VectorXd lambda = cholesky.solve(rhs);
    if (!lambda.allFinite()) {
      throw SolverError(
          "free_seam_target: the system of the seams' curvature gave no finite "
          "solution");
    }
    Eigen::VectorXd u = -(linear_.L * lambda);
    for (int v = 0; v < nv; ++v) u[v] /= 8 * std::max(linear_.area[v], 1e-300);
    u.array() -= linear_.area.dot(u);
    if (multiplier != nullptr) {
      *multiplier = lambda;
      for (int v = 0; v < nv; ++v) {
        if (result.free[v] || t_.vertex_component[v] < 0) (*multiplier)[v] = 0;
      }
    }
    const Eigen::VectorXd curvature = linear_.curvature + linear_.L * u;
    fill_target(linear_, t_, result, prescribed, curvature);
    result.linear_area_energy = seam_area_energy(linear_, t_, u);
    result.linear_u = std::move(u);
    result.seconds = seconds_since(start);
    return result;
  }

 private:
  const cone_steps::LinearFlow& linear_;
  const Topology& t_;
  Eigen::SparseMatrix<double> base_;
  /// Modifies `cholesky`, which holds the system of the free set `held`, into the system of
  /// `free`: false (nothing changed, or the factor lost) when it holds none, when too many
  /// vertices change for updates to pay, or when the backend cannot.
  bool update_held(const std::vector<char>& held, const std::vector<char>& free, double weight,
                   SparseCholesky& cholesky) const {
    if (held.size() != free.size()) return false;
    std::vector<std::pair<int, double>> changes;
    for (int v = 0; v < t_.num_vertices; ++v) {
      if (t_.vertex_component[v] >= 0 && free[v] != held[v]) {
        changes.emplace_back(v, free[v] ? weight : -weight);
      }
    }
    // A change costs about the columns on its path to the elimination tree's root, a
    // factorisation about their sum over every column: on meshes, the break-even grows like
    // sqrt(#V) (bob, 5.3k vertices: 0.07 ms a change against 10-13 ms, about 150; kitten, 53k:
    // 1-1.5 ms against 240 ms, about 180-200).
    const auto limit = static_cast<std::size_t>(std::sqrt(static_cast<double>(t_.num_vertices)));
    if (changes.size() > limit) return false;
    return changes.empty() || cholesky.update_diagonal(changes);
  }

  double beta_ = 0;
  std::array<SparseCholesky, 2> factors_;
  /// The free set whose system each factorisation holds (empty: none, or another system).
  std::array<std::vector<char>, 2> held_;
};

/// The minimiser with the Dirichlet energy for the angles (the file comment's problem):
///     min 4 u^T M u + s u^T L u   subject to   (L u)_v = K-bar_v - K_v, v prescribed,
/// its constraints held by a penalty 1 / delta: with lambda = (C u - b) / delta eliminated from
/// the quasi-definite system [4M + sL, C^T; C, -delta I] (C the prescribed rows of L), u solves
/// the positive definite (4M + sL + C^T C / delta) u = C^T b / delta: the same solution, and the
/// pattern of L L, which CHOLMOD's supernodal factorisation takes (the quasi-definite system in
/// a simplicial LDL^T took 3.8 s on kitten, this 0.4 s, with a residual of the system as small).
/// With `analysed`, the system is factorised in its pattern (that of L L too), by its
/// factorisation `dirichlet_factor`, without an analysis of its own.
FreeSeamTarget solve_dirichlet(const cone_steps::LinearFlow& linear, const Topology& t,
                               std::vector<char> free, const Target& prescribed, double smoothness,
                               SeamSystem* analysed = nullptr, int dirichlet_factor = 1) {
  const auto start = Clock::now();
  const int nv = t.num_vertices;
  FreeSeamTarget result;
  result.free = std::move(free);
  // The prescribed rows' weights (1 / delta) and right-hand sides.
  Eigen::VectorXd weight = Eigen::VectorXd::Zero(nv), b = Eigen::VectorXd::Zero(nv);
  const Eigen::SparseMatrix<double>& L = linear.L;
  const double smooth = smoothness / std::max(1, t.num_faces);
  // delta: small enough that the prescribed rows hold to about delta times the multipliers (the
  // flow then meets them exactly anyway), large enough that the penalty leaves the system
  // well within double precision.
  const double delta = 1e-8 * std::max(1.0, L.diagonal().cwiseAbs().maxCoeff());
  for (int v = 0; v < nv; ++v) {
    if (t.vertex_component[v] < 0) continue;  // a vertex of no face
    if (result.free[v]) {
      ++result.free_vertices;
    } else {
      weight[v] = 1 / delta;
      b[v] = prescribed.curvature[v] - linear.curvature[v];
    }
  }
  // In L L's pattern (the seam system's, when it is given): L W L, then s L, then the diagonal.
  // A vertex of no face keeps u = 0 by its area term alone (its L row is empty).
  Eigen::SparseMatrix<double> system =
      analysed != nullptr ? analysed->pattern() : numerics_detail::square_pattern(L);
  numerics_detail::set_weighted_square(L, weight, system);
  numerics_detail::add_into_pattern(L, smooth, system);
  for (int v = 0; v < nv; ++v) system.coeffRef(v, v) += 4 * std::max(linear.area[v], 1e-300);
  SparseCholesky own;
  SparseCholesky* cholesky = analysed != nullptr ? &analysed->take_factor(dirichlet_factor) : &own;
  try {
    cholesky->factorize(system);
  } catch (const SolverError&) {
    throw SolverError(
        "free_seam_target: the system of the seams' curvature could not be "
        "factorised");
  }
  Eigen::VectorXd u = cholesky->solve(L * weight.cwiseProduct(b));
  if (!u.allFinite()) {
    throw SolverError(
        "free_seam_target: the system of the seams' curvature gave no finite "
        "solution");
  }
  u.array() -= linear.area.dot(u);
  fill_target(linear, t, result, prescribed, linear.curvature + L * u);
  result.linear_area_energy = seam_area_energy(linear, t, u);
  result.linear_u = std::move(u);
  result.seconds = seconds_since(start);
  return result;
}

/// max |u - mean u| over the prescribed vertices (off the cut): the measure the automatic count
/// bounds, as for cones (a seam vertex's own u is what the seam carries, not distortion more
/// cones could remove).
double spread_off_the_cut(const FreeSeamTarget& seams, const cone_steps::LinearFlow& linear) {
  double spread = 0;
  for (Eigen::Index v = 0; v < seams.linear_u.size(); ++v) {
    if (!seams.free[v] && linear.area[v] > 0)
      spread = std::max(spread, std::abs(seams.linear_u[v]));
  }
  return spread;
}

void check_sizes(const Topology& t, const Target& prescribed, const FreeSeamOptions& options,
                 const char* who) {
  if (prescribed.curvature.size() != t.num_vertices ||
      static_cast<int>(prescribed.fixed.size()) != t.num_vertices) {
    throw InvalidInput(std::string(who) + ": the target does not belong to the mesh");
  }
  if (!(options.smoothness >= 0)) {
    throw InvalidInput(std::string(who) + ": smoothness must be >= 0");
  }
}

}  // namespace

FreeSeamTarget free_seam_target(const FlowProblem& problem, const CutGraph& cut,
                                const Target& prescribed, const FreeSeamOptions& options) {
  const auto start = Clock::now();
  const Topology& t = problem.topology;
  check_sizes(t, prescribed, options, "free_seam_target");
  if (static_cast<int>(cut.is_cut_edge.size()) != t.num_edges) {
    throw InvalidInput("free_seam_target: the cut does not belong to the mesh");
  }
  const cone_steps::LinearFlow linear = cone_steps::linearise_flow(problem, "free_seam_target");
  FreeSeamTarget result =
      solve_dirichlet(linear, t, free_vertices(t, cut, prescribed), prescribed, options.smoothness);
  result.seconds = seconds_since(start);
  return result;
}

FreeSeamCones select_free_seam_cones(const FlowProblem& problem, const Target& prescribed,
                                     int count, double max_log_scale,
                                     const CutGraphOptions& cut_options,
                                     const FreeSeamOptions& options) {
  const auto start = Clock::now();
  const Topology& t = problem.topology;
  check_sizes(t, prescribed, options, "select_free_seam_cones");
  // (The squared Laplacian: about 19 entries a row.)
  parallel::Task<void> loading = cone_steps::load_cholmod_beside(t.num_vertices, 19);
  const cone_steps::LinearFlow linear =
      cone_steps::linearise_flow(problem, "select_free_seam_cones");
  SeamSystem system(linear, t, options.selection_smoothness);
  FreeSeamCones result;
  CutGraphOptions cutting = cut_options;
  cutting.cones.clear();
  struct FirstRound {
    CutGraph cut;
    FreeSeamTarget seams;
    Eigen::VectorXd multiplier;
  };
  std::optional<FirstRound> first_round;
  // The factorisation the rounds solve with (each modifying the last round's system), and the
  // other, which the final Dirichlet system takes.
  int rounds_factor = 0;
  if (cutting.root_vertex < 0 && t.components.at(0).genus > 0) {
    // One root for every round: the homology generators all pass through it, and a root that
    // moved with the cones (cut_graph's default) would change the cut's loops from round to
    // round. Of the vertices of most negative and most positive curvature, the one whose
    // generators alone distort less: the loops then meet where curvature is to be taken out
    // anyway.
    int lowest = -1, highest = -1;
    for (int v = 0; v < t.num_vertices; ++v) {
      if (t.vertex_component[v] < 0) continue;
      if (lowest < 0 || linear.curvature[v] < linear.curvature[lowest]) lowest = v;
      if (highest < 0 || linear.curvature[v] > linear.curvature[highest]) highest = v;
    }
    // The two candidates' cuts and solves side by side, each with its own factorisation.
    std::array<FirstRound, 2> candidates;
    const std::array<int, 2> roots = {lowest, highest};
    const auto try_root = [&](int which) {
      CutGraphOptions rooted = cutting;
      rooted.root_vertex = roots.at(which);
      FirstRound& c = candidates.at(which);
      c.cut = cut_graph(t, problem.input_lengths, rooted);
      c.seams = system.solve(free_vertices(t, c.cut, prescribed), prescribed, &c.multiplier, which);
    };
    parallel::run_pair([&] { try_root(0); }, [&] { try_root(1); });
    // The first round's cut and solve (no cones yet, this root): kept, not made again. (The
    // lower energy; the first on a tie.)
    const int better =
        candidates[1].seams.linear_area_energy < candidates[0].seams.linear_area_energy ? 1 : 0;
    if (candidates.at(better).seams.linear_area_energy < INFINITY) {
      result.root = roots.at(better);
      first_round = std::move(candidates.at(better));
      rounds_factor = better;
    }
    cutting.root_vertex = result.root;
  }
  const Component& component = t.components.at(0);
  if (component.genus == 0 && component.num_boundary_loops == 0) {
    // A sphere has no cut before it has cones, so nothing free to solve for: the first cone is
    // the vertex of most positive curvature, where some of its 4 pi is to go anyway.
    int first = -1;
    for (int v = 0; v < t.num_vertices; ++v) {
      if (t.vertex_component[v] >= 0 &&
          (first < 0 || linear.curvature[v] > linear.curvature[first]))
        first = v;
    }
    cutting.cones.push_back(first);
  }
  Eigen::VectorXd multiplier;
  // (cones, spread off the cut) after each round: automatic cones stop once more stop helping
  // (cone_steps::spread_stalled, as the rigid selection's): on noisy scans the spread is held up
  // by bumps no cone set flattens, and the rounds went on to 612 cones on a 5k-face cow and 1542
  // on a 13k-face cheburashka.
  std::vector<std::pair<int, double>> spread_history;
  const int stall_from = cone_steps::stall_check_from(
      component.num_boundary_loops == 0, 2 - 2 * component.genus - component.num_boundary_loops);
  std::vector<int> rings(t.num_vertices);
  const std::vector<std::vector<int>> neighbours = cone_steps::vertex_neighbours(t);
  // The final cut's curvature with the Dirichlet energy (below), when the round that reaches a
  // fixed count solved it beside its own system.
  std::optional<FreeSeamTarget> dirichlet;
  for (;;) {
    const int have = static_cast<int>(cutting.cones.size());
    if (first_round && cutting.cones.empty()) {
      result.cut = std::move(first_round->cut);
      result.seams = std::move(first_round->seams);
      multiplier = std::move(first_round->multiplier);
      first_round.reset();
    } else if (count > 0 && have >= count) {
      // The last round: its cut is final, so the Dirichlet solve need not wait for its own.
      result.cut = cut_graph(t, problem.input_lengths, cutting);
      const std::vector<char> free = free_vertices(t, result.cut, prescribed);
      parallel::run_pair(
          [&] { result.seams = system.solve(free, prescribed, &multiplier, rounds_factor); },
          [&] {
            dirichlet = solve_dirichlet(linear, t, free, prescribed, options.smoothness, &system,
                                        1 - rounds_factor);
          });
    } else {
      result.cut = cut_graph(t, problem.input_lengths, cutting);
      result.seams = system.solve(free_vertices(t, result.cut, prescribed), prescribed, &multiplier,
                                  rounds_factor);
    }
    if (count > 0) {
      if (have >= count) break;
    } else {
      const double spread = spread_off_the_cut(result.seams, linear);
      spread_history.emplace_back(have, spread);
      if (spread <= max_log_scale || cone_steps::spread_stalled(spread_history, stall_from)) break;
    }
    // The next cones: the prescribed vertices whose rows' multipliers are largest, in a batch
    // (half as many as are placed, at least one: each round costs a factorisation), each a few
    // rings from the free vertices and from the others of the batch, so that their paths to
    // the cut open new regions.
    const int batch = std::max(1, have / 2);
    const int wanted = count > 0 ? std::min(count - have, batch) : batch;
    std::vector<int> frontier;
    for (int v = 0; v < t.num_vertices; ++v) {
      if (result.seams.free[v]) frontier.push_back(v);
    }
    auto grow = [&](std::vector<int> from, int depth) {
      for (int r = 1; r <= depth && !from.empty(); ++r) {
        std::vector<int> next;
        for (int a : from) {
          for (int b : neighbours[a]) {
            if (rings[b] < 0) rings[b] = r, next.push_back(b);
          }
        }
        from = std::move(next);
      }
    };
    // Three rings, fewer where none is left that far (small meshes).
    int kRings = 3;
    std::vector<int> order;
    for (; kRings >= 1; --kRings) {
      std::fill(rings.begin(), rings.end(), -1);
      for (int v : frontier) rings[v] = 0;
      grow(frontier, kRings);
      order.clear();
      for (int v = 0; v < t.num_vertices; ++v) {
        if (rings[v] < 0 && t.vertex_component[v] >= 0) order.push_back(v);
      }
      if (!order.empty()) break;
    }
    std::sort(order.begin(), order.end(), [&](int a, int b) {
      return std::abs(multiplier[a]) > std::abs(multiplier[b]) ||
             (std::abs(multiplier[a]) == std::abs(multiplier[b]) && a < b);
    });
    int added = 0;
    for (int v : order) {
      if (added == wanted) break;
      if (rings[v] >= 0) continue;  // near a cone of this batch
      cutting.cones.push_back(v);
      rings[v] = 0;
      grow({v}, kRings);
      ++added;
    }
    if (added == 0) break;  // every vertex is near the cut
  }
  for (int v : cutting.cones) result.cones.push_back(v);
  // The final cut's curvature with the Dirichlet energy; the selection's own where that distorts
  // more in the model (a guard on the penalised system's accuracy).
  if (!dirichlet) {
    dirichlet = solve_dirichlet(linear, t, result.seams.free, prescribed, options.smoothness,
                                &system, 1 - rounds_factor);
  }
  if (dirichlet->linear_area_energy <= 10 * result.seams.linear_area_energy) {
    result.seams = std::move(*dirichlet);
  }
  result.seams.seconds = seconds_since(start);
  return result;
}

}  // namespace ricci
