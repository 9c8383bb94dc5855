#pragma once
/// \file
/// The objective automatic cones minimise (internal): the area distortion of the linearised
/// model in log form plus the Dirichlet energy for the angles, over the curvatures of a cone set,
/// and its quasi-Newton minimiser with bounded quadratic steps. cone_selection_steps.cpp fits
/// each cone set with it; cones.cpp measures a flat metric's area distortion with area_energy.

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "ricci/mesh/topology.hpp"
#include "ricci/numerics/sparse_cholesky.hpp"

namespace ricci::cone_steps {

/// Each vertex's faces, one entry per corner, in increasing face order (compressed rows:
/// faces[offset[v]] to faces[offset[v + 1] - 1]).
struct VertexFaces {
  std::vector<int> offset, faces;
};
VertexFaces vertex_faces(const Topology& t);

/// x's mean over the corners of each face ((x_a + x_b + x_c) / 3: area_energy's u_f), in
/// parallel when asked (the same values either way).
Eigen::VectorXd face_means(const Topology& t, const Eigen::VectorXd& x, bool in_parallel = false);

/// The area distortion of the tutorial's eq. 9 as the linearised model sees it, in log form:
///     F(u) = log sum_f a_f e^{4 u_f} - 2 log sum_f a_f e^{2 u_f}  =  log(1 + E),
/// E = sum_f a_f (e^{2 u_f} / Z - 1)^2 with Z = sum_f a_f e^{2 u_f}, u_f the mean of u over the
/// corners of face f (its area scales by e^{2 u_f} when u is linear over it) and a_f its share
/// of the 3D area: the checker's E. Unlike the L2 norm of u it charges expansion exponentially:
/// a strong positive cone (u ~ -(k / 2 pi) log r next to it, so area grows like r^(-k / pi))
/// costs what it costs in the texture, and shrinking costs little. (Per face rather than per
/// vertex: a cone's own u counts once per vertex but touches deg faces; on spot with 4 cones
/// the per-vertex form gave the checker's E 1.01, this one 0.92.)
/// Returns F; `gradient` (optional) gets dF/du. With `incidence` (vertex_faces(t)) the passes
/// over the faces and the gradient's gather per vertex run in parallel, with the same sums in
/// the same order as the sequential passes (the same bits whatever the thread count).
double area_energy(const Topology& t, const Eigen::VectorXd& face_area, const Eigen::VectorXd& u,
                   Eigen::VectorXd* gradient, const VertexFaces* incidence = nullptr);

/// A cone's column of A^-1 (g = A^-1 e_s: how u answers a unit of curvature there), with what
/// the objective's evaluations read of it: its mean over each face and g . rhs0. `faces` is
/// empty when the selection cannot afford #F more doubles per cone (then the evaluations work on
/// the vertices).
struct ConeColumn {
  Eigen::VectorXd g;
  Eigen::VectorXd faces;
  double rhs0_dot = 0;
};
/// Columns are shared, never changed once made: a copy of the selection's state (the exchanges'
/// look-ahead) copies pointers, not #V + #F values per cone.
using SharedColumn = std::shared_ptr<const ConeColumn>;

/// An evaluation of the ConeObjective at curvatures k: its value and gradient in k.
struct ObjectiveValue {
  double value = 0;
  Eigen::VectorXd gradient;
};

/// The objective the cone curvatures minimise: log(1 + E) of the linearised flat metric plus
/// `smooth` times its Dirichlet energy D = sum over edges of w_ij (u_i - u_j)^2 = u^T L u. The
/// second term stands for the angle distortion: a discrete conformal map distorts each face's
/// angles by about |grad u| h, so the mean over faces of the squared distortion is about D / #F
/// (h^2 / area is about constant on a fair mesh); it also charges each cone k^2 G_ss, the log
/// singularity its ring of faces pays. Strong cones of both signs side by side flatten the area
/// and steepen u between them: E alone chose them on spot (angle distortion 1.077 against BFF's
/// 1.058 at 32 cones, its excess far from the cones).
/// With u = A^-1 rhs, rhs = rhs0 + sum_i k_i e_{S_i}: D = u . rhs (held vertices have u = 0), so
/// dD/dk_i = 2 u_{S_i} and its Hessian is 2 A^-1 restricted to S (`green`).
struct ConeObjective {
  const SparseCholesky& cholesky;
  const Eigen::VectorXd& rhs0;
  const Eigen::VectorXd& u0;  ///< A^-1 rhs0
  const Topology& t;
  const Eigen::VectorXd& face_area;
  const std::vector<int>& S;
  /// The cones' columns, when kept (then u and the cones' gradient take no solve); empty when
  /// they would take too much memory.
  const std::vector<SharedColumn>& columns;
  double smooth = 0;
  /// The model's vertex_faces: area_energy in parallel (null: sequential).
  const VertexFaces* incidence = nullptr;
  /// u0's mean over each face and u0 . rhs0: with every column's `faces` an evaluation never
  /// touches the vertices (u_f = u0_f + sum_i k_i g_i,f), see evaluate.
  const Eigen::VectorXd* u0_faces = nullptr;
  double u0_rhs0 = 0;
  /// A^-1 restricted to S (green(i, j) = g_j at S_i): u at the cones without u.
  const Eigen::MatrixXd* green = nullptr;
  /// minimise_cone_objective stops once a step lowers the objective by at most this, relative to
  /// 1 + |F| (the selection's choice: cone_selection_steps.cpp, cone_objective).
  double relative_decrease = 1e-8;

  bool has_columns() const { return !S.empty() && columns.size() == S.size(); }
  /// Whether evaluate works on the faces alone.
  bool on_faces() const {
    if (!has_columns() || u0_faces == nullptr || green == nullptr ||
        green->rows() != static_cast<Eigen::Index>(S.size())) {
      return false;
    }
    for (const SharedColumn& c : columns) {
      if (c->faces.size() != t.num_faces) return false;
    }
    return true;
  }
  Eigen::VectorXd solve_u(const Eigen::VectorXd& k) const {
    if (has_columns()) {
      Eigen::VectorXd u = u0;
      for (std::size_t i = 0; i < S.size(); ++i) u += k[static_cast<int>(i)] * columns[i]->g;
      return u;
    }
    Eigen::VectorXd rhs = rhs0;
    for (std::size_t i = 0; i < S.size(); ++i) rhs[S[i]] += k[static_cast<int>(i)];
    return cholesky.solve(rhs);
  }
  /// The objective at u = solve_u(k); `dfdu` (optional) gets dF/du of its area part, from the
  /// same pass over the faces (the quasi-Newton iterations then take one pass per point).
  double value(const Eigen::VectorXd& u, const Eigen::VectorXd& k,
               Eigen::VectorXd* dfdu = nullptr) const {
    double dirichlet = u.dot(rhs0);
    for (std::size_t i = 0; i < S.size(); ++i) dirichlet += u[S[i]] * k[static_cast<int>(i)];
    return area_energy(t, face_area, u, dfdu, incidence) + smooth * dirichlet;
  }
  /// d/dk_i for the cones: G_S^T dF/du + 2 smooth u_S, given dF/du at u.
  Eigen::VectorXd gradient(const Eigen::VectorXd& u, const Eigen::VectorXd& dfdu) const {
    const int m = static_cast<int>(S.size());
    Eigen::VectorXd g(m);
    if (has_columns()) {
      for (int i = 0; i < m; ++i) g[i] = columns[i]->g.dot(dfdu) + 2 * smooth * u[S[i]];
    } else {
      const Eigen::VectorXd all = cholesky.solve(dfdu);
      for (int i = 0; i < m; ++i) g[i] = all[S[i]] + 2 * smooth * u[S[i]];
    }
    return g;
  }
  /// The same, dF/du computed here.
  Eigen::VectorXd gradient(const Eigen::VectorXd& u) const {
    Eigen::VectorXd dfdu;
    area_energy(t, face_area, u, &dfdu, incidence);
    return gradient(u, dfdu);
  }
  /// The value and the gradient in k at k, the same bits whatever the thread count. With the
  /// columns' face means (on_faces()): two passes over them (#F x #S) and no per-vertex work,
  /// u_f = u0_f + sum_i k_i g_i,f and dF/dk_i = sum_f dF/du_f g_i,f. With the columns alone: u a
  /// block of vertices at a time, area_energy, each column against dF/du. D comes from
  /// g_i . rhs0 and green either way. Without columns: through solve_u, value and gradient.
  ObjectiveValue evaluate(const Eigen::VectorXd& k) const;
  /// d/dk at every vertex (a cone of curvature 0 there included): A^-1 dF/du + 2 smooth u,
  /// given dF/du at u.
  Eigen::VectorXd gradient_everywhere(const Eigen::VectorXd& u, const Eigen::VectorXd& dfdu) const {
    return cholesky.solve(dfdu) + 2 * smooth * u;
  }
};

/// Curvatures k of the cones S minimising the ConeObjective subject to lo <= k <= hi and, on a
/// closed surface, sum k = total: a quasi-Newton method (BFGS started from the objective's
/// Hessian at u = 0: 8 M for log(1 + E), M = G_S^T P G_S the Hessian of J, plus 2 smooth green)
/// whose steps are the bounded quadratic programmes of bounded_least_squares, with a backtracking
/// line search. With the cones' columns of A^-1 kept an iterate takes no solve (dense products
/// of #V x #S); without them two. `k` enters feasible (the J minimiser) and leaves at the
/// minimiser; returns u there, `gradient_all` (when given) gets the objective's gradient at
/// every vertex (for the next cone: the one solve of the call with columns). B: in, an estimate
/// of the Hessian for the first B.rows() cones (from an earlier call); out, the final one.
Eigen::VectorXd minimise_cone_objective(const ConeObjective& objective, const Eigen::MatrixXd& M,
                                        const Eigen::MatrixXd& green, const Eigen::VectorXd& lo,
                                        const Eigen::VectorXd& hi, bool closed, double total,
                                        Eigen::VectorXd& k, Eigen::MatrixXd& B,
                                        Eigen::VectorXd* gradient_all, double& value);

}  // namespace ricci::cone_steps
