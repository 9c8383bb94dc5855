#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/Dense>

#include "param/cones/detail/cone_objective.hpp"
#include "param/cones/detail/cone_selection_steps.hpp"
#include "ricci/errors.hpp"
#include "ricci/param/cones/cones.hpp"

namespace ricci {
namespace {

using cone_steps::ConeModelData;

/// Exchange passes after the greedy (Gauss-Seidel sweeps over the cones).
constexpr int kLevelExchangePasses = 4;

/// The model's columns A^-1 e_v, solved once per vertex asked for.
class GreenColumns {
 public:
  explicit GreenColumns(const ConeModelData& model) : model_(model) {}
  const Eigen::VectorXd& of(int v) {
    auto it = columns_.find(v);
    if (it != columns_.end()) return it->second;
    Eigen::VectorXd e = Eigen::VectorXd::Zero(model_.nv);
    e[v] = 1;
    return columns_.emplace(v, model_.cholesky.solve(e)).first->second;
  }

 private:
  const ConeModelData& model_;
  std::unordered_map<int, Eigen::VectorXd> columns_;
};

/// The linearised flat metric whose log scale is one common level at every cone (a closed
/// surface: the curvatures sum to 2 pi chi and the level is free; with a boundary: the
/// boundary's level, 0): the cones' curvatures k and u less that level.
struct LevelFit {
  Eigen::VectorXd k, u;
};

LevelFit fit_level(const ConeModelData& model, const Eigen::VectorXd& u0, GreenColumns& green,
                   const std::vector<int>& S) {
  const int m = static_cast<int>(S.size());
  const int n = model.closed ? m + 1 : m;
  Eigen::MatrixXd system = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd rhs(n);
  for (int i = 0; i < m; ++i) {
    const Eigen::VectorXd& column = green.of(S[i]);
    for (int j = 0; j < m; ++j) system(j, i) = column[S[j]];
    rhs[i] = -u0[S[i]];
  }
  if (model.closed) {
    // u_S + c = 0 and sum k = 2 pi chi (with it the right-hand side sums to 0, so the model's
    // gauge vertex is at u = 0 like any other solution of L u = K-bar - K).
    for (int i = 0; i < m; ++i) {
      system(i, m) = 1;
      system(m, i) = 1;
    }
    rhs[m] = 2 * std::numbers::pi * model.chi;
  }
  const Eigen::VectorXd x = system.fullPivLu().solve(rhs);
  LevelFit fit;
  fit.k = x.head(m);
  fit.u = u0;
  for (int i = 0; i < m; ++i) fit.u += fit.k[i] * green.of(S[i]);
  if (model.closed) fit.u.array() += x[m];
  return fit;
}

/// The vertex (not held, not a cone) where |u| is largest; -1 when there is none.
int most_scaled(const ConeModelData& model, const Eigen::VectorXd& u, const std::vector<int>& S) {
  int best = -1;
  for (int v = 0; v < model.nv; ++v) {
    if (model.held[v] || model.topology->vertex_component[v] < 0 ||
        std::find(S.begin(), S.end(), v) != S.end()) {
      continue;
    }
    if (best < 0 || std::abs(u[v]) > std::abs(u[best])) best = v;
  }
  return best;
}

}  // namespace

ConeSelection select_level_cones(const ConeModel& handle, int count) {
  const ConeModelData& model = handle.data();
  if (count < 1) {
    throw InvalidInput("select_level_cones: count must be >= 1, got " + std::to_string(count));
  }
  GreenColumns green(model);
  const Eigen::VectorXd u0 = model.cholesky.solve(model.rhs0);
  std::vector<int> S;
  ConeSelection result;
  if (model.closed) {
    // The first cone where the metric of constant curvature (2 pi chi spread by area) scales
    // most: no single cone flattens a closed surface, so its flat metric cannot say.
    Eigen::VectorXd rhs = model.rhs0 + 2 * std::numbers::pi * model.chi * model.area;
    Eigen::VectorXd u = model.cholesky.solve(rhs);
    u.array() -= model.area.dot(u);
    const int first = most_scaled(model, u, S);
    if (first < 0) throw InvalidInput("select_level_cones: no vertex can take a cone");
    S.push_back(first);
  }
  while (static_cast<int>(S.size()) < count) {
    const LevelFit fit =
        S.empty() ? LevelFit{Eigen::VectorXd(), u0} : fit_level(model, u0, green, S);
    const int v = most_scaled(model, fit.u, S);
    if (v < 0) break;
    S.push_back(v);
  }
  // Passes of exchanges: each cone moved to where the others leave the log scale largest.
  for (int pass = 0; pass < kLevelExchangePasses; ++pass) {
    for (std::size_t i = 0; i < S.size(); ++i) {
      std::vector<int> others = S;
      others.erase(others.begin() + static_cast<std::ptrdiff_t>(i));
      const LevelFit fit = others.empty() && !model.closed ? LevelFit{Eigen::VectorXd(), u0}
                                                           : fit_level(model, u0, green, others);
      const int v = most_scaled(model, fit.u, others);
      if (v >= 0) S[i] = v;
    }
  }
  const LevelFit fit = fit_level(model, u0, green, S);
  result.vertices = S;
  result.linear_curvature.assign(fit.k.data(), fit.k.data() + fit.k.size());
  result.within_bounds = true;
  result.area_energy =
      std::expm1(cone_steps::area_energy(*model.topology, model.face_area, fit.u, nullptr));
  const Eigen::VectorXd Pu = model.spread(fit.u);
  result.log_scale_rms = std::sqrt(std::max(0.0, fit.u.dot(Pu)));
  return result;
}

}  // namespace ricci
