#pragma once
/// \file
/// The steps of select_cones (internal): the linearised model it works on, its working state,
/// and the named steps (seed, add, fit, grow, exchange, quantize) that cones.cpp defines and
/// tests/param/cones/cone_selection_steps_test.cpp pins down one by one.

#include <limits>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "param/cones/detail/cone_objective.hpp"
#include "ricci/metric/angles.hpp"
#include "ricci/numerics/sparse_cholesky.hpp"
#include "ricci/param/cones/cones.hpp"

namespace ricci::cone_steps {

/// The flow linearised at the input metric, factorised once: what the selection and the
/// refinement of cone curvatures share.
struct ConeModelData {
  const Topology* topology = nullptr;  ///< the problem's
  int nv = 0;
  bool closed = false;
  int chi = 0;
  int gauge = -1;          ///< closed surfaces: the vertex held at u = 0
  std::vector<char> held;  ///< boundary vertices and the gauge, held at u = 0
  Eigen::VectorXd curvature, area, angle_sum, largest_corner;
  Eigen::VectorXd face_area;                 ///< each face's share of the 3D area
  VertexFaces vertex_faces;                  ///< of the topology (area_energy in parallel)
  std::vector<std::vector<int>> neighbours;  ///< vertex_neighbours of the topology
  CornerAngles angles;
  Eigen::SparseMatrix<double> A;  ///< L plus the penalty on the held vertices
  SparseCholesky cholesky;
  Eigen::VectorXd rhs0;  ///< -K off the held vertices: u0 = A^-1 rhs0

  /// P x = a (x - mean_a x): J = u^T P u.
  Eigen::VectorXd spread(const Eigen::VectorXd& x) const {
    const double mean = area.dot(x);
    return (area.array() * (x.array() - mean)).matrix();
  }
};

/// The last cone set whose curvatures met their bounds: when automatic selection ends out of
/// bounds (the cap, or cones so close together on a needle mesh that the bounded problem had
/// no solution and its unbounded fallback gave curvatures of +-36), it returns that one.
struct LastGood {
  int m = 0;
  Eigen::VectorXd k;
  double rms = 0;
};

/// select_cones' working state: the cone set S and what the model knows about it.
struct ConeSelector {
  ConeSelector(const ConeModelData& m, const ConeSelectionOptions& o) : model(m), options(o) {}

  const ConeModelData& model;
  const ConeSelectionOptions& options;
  Eigen::VectorXd u0;   ///< A^-1 rhs0: u without cones
  Eigen::VectorXd Pu0;  ///< P u0
  double upper = 0;     ///< every cone's upper curvature bound (options.max_curvature)
  double smooth = 0;    ///< weight of the Dirichlet energy per face (see ConeObjective)
  double total = 0;     ///< 2 pi chi: what the curvatures sum to on a closed surface
  int max_cones = 0;    ///< the cap (options.max_cones, else #V: none)
  int wanted = -1;      ///< count mode: the number of cones; -1 automatic
  /// A cone of curvature k makes u behave like -(k / 2 pi) log r next to it: the cone itself,
  /// not distortion more cones could remove. Vertices within `separation` rings of a cone are
  /// left out of the measure and of the candidates (else cones pile up next to each other).
  int separation = 0;
  std::vector<int> ring;  ///< hops to the nearest cone, counted up to `separation`
  std::vector<int> S;     ///< the cones, in the order they were added
  /// M = G_S^T P G_S (J's Hessian), green = A^-1 restricted to S, r = G_S^T P u0.
  Eigen::MatrixXd M, green;
  Eigen::VectorXd r;
  std::vector<char> is_cone;
  /// Vertices of a face with a corner above max_corner_angle: a cone there steepens u across
  /// that face, whose angle distortion (the checker's face mean) then explodes or whose corner
  /// images cross (a CAD cylinder's fan: one 178.5-degree face next to an exchanged cone took
  /// sigma ratio 2836 and the mean from 1.79 to 4.15; lifted valence-3 spikes, 141-degree
  /// corners: 6 flipped faces, 2 with this). They are candidates only when no other vertex is.
  std::vector<char> on_sliver;
  /// The cones' columns of A^-1, kept while they fit in kColumnValues doubles (the objective's
  /// iterations then take no solve, and M comes from dot products); empty otherwise. Their means
  /// over the faces too while those fit as well (the iterations then work on the faces alone).
  std::vector<SharedColumn> columns;
  Eigen::VectorXd u0_faces;  ///< u0's mean over each face
  double u0_rhs0 = 0;        ///< u0 . rhs0
  Eigen::MatrixXd hessian;   ///< the objective's quasi-Newton Hessian at the previous fit
  /// (cones, max |u - mean u|) after each fit of the greedy: when more cones stop helping
  std::vector<std::pair<int, double>> spread_history;
  LastGood last_good;
};

/// The curvatures of the current cone set: the J minimiser (a bounded quadratic programme),
/// then the objective's (warm-started from the previous greedy step when given a start).
struct SetFit {
  bool within = true;  ///< the bounds could be met
  double value = INFINITY, lambda = 0;
  Eigen::VectorXd k, u, q;  ///< q: the gradient at every vertex (J's when out of bounds)
};

/// The state before any cone: u0, the rings, the slivers, the cap and count.
ConeSelector make_cone_selector(const ConeModelData& model, const ConeSelectionOptions& options);

/// The lowest curvature a cone at v may take (drawable on the input's faces).
double cone_lower_bound(const ConeModelData& model, const ConeSelectionOptions& options, int v);

/// The objective over the cones `cones` (S or a prefix of it) with what the selector keeps.
ConeObjective cone_objective(const ConeSelector& selector, const std::vector<int>& cones);

/// Adds a cone at v: extends M, green, r (and the columns while they fit) and its rings.
void add_cone(ConeSelector& selector, int v);
/// Recomputes the rings of the cones S at the current separation.
void reset_rings(ConeSelector& selector);

/// The first cone's candidates on a closed surface of chi != 0: the vertex of most extreme
/// curvature (of the sign of chi), then farthest-point samples in edge hops, at most
/// options.try_first_cone_candidates (at least one); never the gauge.
std::vector<int> first_cone_candidates(const ConeSelector& selector);
/// Seed: among first_cone_candidates, the one whose single cone of 2 pi chi spreads u least
/// (smallest u^T P u); it makes the problem solvable.
int seed_cone(const ConeSelector& selector);

/// Fit: the curvatures of the cones S (bounded; on a closed surface summing to 2 pi chi), the
/// J minimiser refined to the objective's when in bounds. `start` (may be null) warm-starts
/// the objective when it lies in the bounds; need_q asks for the gradient at every vertex.
/// Updates selector.hessian.
SetFit fit_cone_set(ConeSelector& selector, const Eigen::VectorXd* start, bool need_q);
/// The best candidate for a new cone by the fit's gradient q (not held, not a cone, outside
/// the rings of the cones, and on a closed surface with a lower bound the total can still
/// pay); -1 when there is none.
int best_candidate(const ConeSelector& selector, const SetFit& fit);
/// Add: a batch of the best candidates by |q + lambda| (max(1, #S / 8), within the cap).
/// Returns false when the greedy must stop (no candidate keeps the bounds feasible, or none
/// is left even with the cones next to each other); when none is left outside the rings, it
/// lets the cones come one ring closer and returns true without adding.
bool add_cones(ConeSelector& selector, const SetFit& fit);
/// Grow: fit, record and add until the count is reached (count mode) or the log scale is
/// within options.max_log_scale in bounds, or the cap. Fills result's diagnostics (not its
/// vertices); returns the last fit.
SetFit grow_cone_set(ConeSelector& selector, ConeSelection& result);
/// Exchange: each cone in turn taken out and the best candidate for the others put in its
/// place, kept when the objective falls (`fit` then becomes the new set's); two passes up to
/// kExchangeTwice cones, else one. Returns whether any exchange was kept.
bool exchange_cones(ConeSelector& selector, SetFit& fit);
/// Quantize: curvatures in quarter turns for `cones` (a prefix of S or S itself), rounded
/// keeping the sum (2 pi chi on a closed surface), then a quarter turn moved from one cone to
/// another while the objective falls.
Eigen::VectorXd quantize_in_model(const ConeSelector& selector, const std::vector<int>& cones,
                                  const Eigen::VectorXd& k_real);

/// Rings around a cone left out of the measure and of the candidates for the next cone. (Capping
/// them by area in the selection let cones crowd on small high-genus meshes: 2 flipped faces on
/// a generated genus-20 surface of 748 faces.)
inline constexpr int kSeparationRings = 3;

/// The ring count of a vertex no cone's rings reach: above any count of rings.
inline constexpr int kFarFromCones = std::numeric_limits<int>::max() / 2;

/// Each vertex's neighbours along the edges, in edge order.
std::vector<std::vector<int>> vertex_neighbours(const Topology& t);

/// The fewest automatic cones (without a cap) at which spread_stalled may stop a selection on a
/// component of Euler characteristic chi: 64, or 6 |chi| on a closed surface of chi < 0, whose
/// curvature needs about that many cones within their bounds (each takes at most about pi on a
/// valence-6 vertex).
int stall_check_from(bool closed, int chi);

/// Automatic count without a cap: whether more cones stopped helping. history holds (cones,
/// measure of the log scale's spread) after each round; true once the count is at least `from`
/// and the measure with half as many cones (or fewer) was hardly larger than now (not above
/// now / 0.95). The greedy selection and the free seams' selection share it.
bool spread_stalled(const std::vector<std::pair<int, double>>& history, int from);

}  // namespace ricci::cone_steps

namespace ricci {
struct ConeModel::Data : cone_steps::ConeModelData {};
}  // namespace ricci
