// The named steps of select_cones (src/param/cones/detail/cone_selection_steps.hpp), each
// against its contract on a generated closed surface.
#include "param/cones/detail/cone_selection_steps.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "ricci/flow/flow_problem.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/topology.hpp"
#include "support/scoped_threads.hpp"

namespace ricci {
namespace {

using namespace cone_steps;

/// The bounded programme meets its sum to the active-set solve's rounding (1e-12 relative to
/// curvatures of order pi) and its bounds to the violation tolerance 1e-12.
constexpr double kTolerance = 1e-9;

/// A problem, its model and a selector on it (the model points into the problem).
struct Fixture {
  explicit Fixture(const Mesh& mesh, ConeSelectionOptions selection = {})
      : options(selection),
        problem(make_flow_problem(mesh, options.structure)),
        model(build_cone_model(problem)) {}
  ConeSelectionOptions options;
  FlowProblem problem;
  ConeModel model;
  const ConeModelData& data() const { return model.data(); }
  ConeSelector selector() const { return make_cone_selector(data(), options); }
};

ConeSelectionOptions with_count(int count) {
  ConeSelectionOptions options;
  options.count = count;
  return options;
}

/// A selector on the closed sphere, seeded and grown towards `count` cones, with the fit and
/// the selection that grow_cone_set ended on.
struct Grown {
  explicit Grown(int count)
      : fixture(make_closed_surface(0, 16), with_count(count)), selector(fixture.selector()) {
    add_cone(selector, seed_cone(selector));
    fit = grow_cone_set(selector, result);
  }
  // The selector points into the fixture: a copy would point into the original.
  Grown(const Grown&) = delete;
  Grown& operator=(const Grown&) = delete;

  Fixture fixture;
  ConeSelector selector;
  ConeSelection result;
  SetFit fit;
};

/// u^T P u of the single cone of 2 pi chi at c.
double single_cone_spread(const ConeModelData& model, double total, int c) {
  Eigen::VectorXd rhs = model.rhs0;
  rhs[c] += total;
  const Eigen::VectorXd u = model.cholesky.solve(rhs);
  return u.dot(model.spread(u));
}

TEST(ConeSteps, SeedTakesTheLeastSpreadingOfWellSpreadCandidates) {
  const Fixture fixture(make_closed_surface(0, 16));
  const ConeModelData& model = fixture.data();
  const ConeSelector selector = fixture.selector();
  ASSERT_TRUE(model.closed);
  ASSERT_EQ(model.chi, 2);
  const std::vector<int> candidates = first_cone_candidates(selector);
  ASSERT_FALSE(candidates.empty());
  EXPECT_LE(static_cast<int>(candidates.size()), fixture.options.try_first_cone_candidates);
  // The first candidate: the vertex of largest curvature (chi > 0), never the gauge.
  for (int v = 0; v < model.nv; ++v) {
    if (v != model.gauge) {
      EXPECT_LE(model.curvature[v], model.curvature[candidates[0]]);
    }
  }
  std::vector<int> sorted = candidates;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(std::unique(sorted.begin(), sorted.end()), sorted.end());
  EXPECT_EQ(std::count(candidates.begin(), candidates.end(), model.gauge), 0);
  // The seed is the candidate whose single cone spreads u least.
  const int seed = seed_cone(selector);
  ASSERT_NE(std::find(candidates.begin(), candidates.end(), seed), candidates.end());
  const double seed_spread = single_cone_spread(model, selector.total, seed);
  for (int c : candidates) EXPECT_LE(seed_spread, single_cone_spread(model, selector.total, c));
}

TEST(ConeSteps, AddExtendsTheModelMatricesSymmetrically) {
  const Fixture fixture(make_closed_surface(0, 16));
  ConeSelector selector = fixture.selector();
  add_cone(selector, seed_cone(selector));
  const SetFit fit = fit_cone_set(selector, nullptr, true);
  const int v = best_candidate(selector, fit);
  ASSERT_GE(v, 0);
  EXPECT_FALSE(selector.is_cone[v]);
  EXPECT_GT(selector.ring[v], selector.separation);
  add_cone(selector, v);
  ASSERT_EQ(selector.S.size(), 2u);
  EXPECT_EQ(selector.S.back(), v);
  EXPECT_TRUE(selector.is_cone[v]);
  EXPECT_EQ(selector.ring[v], 0);
  ASSERT_EQ(selector.M.rows(), 2);
  ASSERT_EQ(selector.green.rows(), 2);
  ASSERT_EQ(selector.r.size(), 2);
  EXPECT_EQ(selector.M(0, 1), selector.M(1, 0));
  EXPECT_EQ(selector.green(0, 1), selector.green(1, 0));
  // green = A^-1 restricted to S: its entry (1, 1) is the solve of the unit source at v.
  Eigen::VectorXd e = Eigen::VectorXd::Zero(fixture.data().nv);
  e[v] = 1;
  EXPECT_NEAR(selector.green(1, 1), fixture.data().cholesky.solve(e)[v], 1e-12);
}

TEST(ConeSteps, FitSatisfiesGaussBonnetAndTheBounds) {
  const Fixture fixture(make_closed_surface(0, 16));
  ConeSelector selector = fixture.selector();
  add_cone(selector, seed_cone(selector));
  int within = 0;
  for (int n = 0; n < 6; ++n) {
    const SetFit fit = fit_cone_set(selector, nullptr, true);
    const int m = static_cast<int>(selector.S.size());
    ASSERT_EQ(fit.k.size(), m);
    EXPECT_EQ(fit.q.size(), fixture.data().nv);
    // The sum holds in bounds and out (one cone cannot carry 4 pi: the fallback ignores the
    // bounds, not the sum).
    EXPECT_NEAR(fit.k.sum(), 4 * std::numbers::pi, kTolerance);
    if (fit.within) {
      ++within;
      for (int i = 0; i < m; ++i) {
        EXPECT_GE(fit.k[i],
                  cone_lower_bound(fixture.data(), fixture.options, selector.S[i]) - kTolerance);
        EXPECT_LE(fit.k[i], selector.upper + kTolerance);
      }
      EXPECT_TRUE(std::isfinite(fit.value));
    }
    ASSERT_TRUE(add_cones(selector, fit));
  }
  EXPECT_GT(within, 0);
}

TEST(ConeSteps, GrowStopsAtTheWantedCount) {
  const Grown grown(5);
  EXPECT_EQ(grown.selector.S.size(), 5u);
  EXPECT_EQ(grown.fit.k.size(), 5);
  EXPECT_TRUE(grown.result.within_bounds);
  EXPECT_FALSE(grown.result.max_log_scale.empty());
  EXPECT_NEAR(grown.fit.k.sum(), 4 * std::numbers::pi, kTolerance);
}

TEST(ConeSteps, ExchangeNeverIncreasesTheObjective) {
  Grown grown(6);
  ASSERT_TRUE(grown.fit.within);
  const double before = grown.fit.value;
  exchange_cones(grown.selector, grown.fit);
  EXPECT_LE(grown.fit.value, before);
  EXPECT_TRUE(grown.fit.within);
  ASSERT_EQ(grown.selector.S.size(), 6u);
  std::vector<int> sorted = grown.selector.S;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(std::unique(sorted.begin(), sorted.end()), sorted.end());
  for (int v : grown.selector.S) EXPECT_TRUE(grown.selector.is_cone[v]);
  EXPECT_NEAR(grown.fit.k.sum(), 4 * std::numbers::pi, kTolerance);
}

// Each exchange's first half is fitted beside the one before it (a look-ahead on a copy of the
// state): on one thread (no look-ahead runs beside) or two, the same cones and the same bits.
TEST(ConeSteps, ExchangesAreTheSameOnOneThreadOrTwo) {
  std::vector<int> cones[2];
  Eigen::VectorXd curvatures[2];
  double values[2] = {0, 0};
  int kept[2] = {0, 0};
  for (int run = 0; run < 2; ++run) {
    const testing::ScopedThreads scoped(run == 0 ? "1" : "2");
    Grown grown(6);
    const std::vector<int> before = grown.selector.S;
    exchange_cones(grown.selector, grown.fit);
    cones[run] = grown.selector.S;
    curvatures[run] = grown.fit.k;
    values[run] = grown.fit.value;
    for (int v : cones[run]) kept[run] += std::count(before.begin(), before.end(), v) ? 0 : 1;
  }
  EXPECT_GT(kept[0], 0) << "no exchange was kept: the look-ahead's discarding is not exercised";
  EXPECT_EQ(cones[0], cones[1]);
  EXPECT_EQ(values[0], values[1]);
  ASSERT_EQ(curvatures[0].size(), curvatures[1].size());
  EXPECT_TRUE((curvatures[0].array() == curvatures[1].array()).all());
}

TEST(ConeSteps, QuantizeGivesQuarterTurnsWithTheSumKept) {
  const Grown grown(8);
  const Eigen::VectorXd kq = quantize_in_model(grown.selector, grown.selector.S, grown.fit.k);
  ASSERT_EQ(kq.size(), grown.fit.k.size());
  for (int i = 0; i < kq.size(); ++i) {
    const double units = kq[i] / (std::numbers::pi / 2);
    EXPECT_NEAR(units, std::round(units), 1e-12);
    EXPECT_LE(kq[i], grown.selector.upper + 1e-12);
  }
  EXPECT_NEAR(kq.sum(), 4 * std::numbers::pi, 1e-12);
}

// The stop both automatic selections share (the greedy's, the free seams'): only from `from`
// cones on, and only when twice the cones bought less than 5 % of the spread.
TEST(ConeSteps, SpreadStallsOnceDoublingTheConesBuysLessThanFivePercent) {
  EXPECT_FALSE(spread_stalled({}, 64));
  EXPECT_FALSE(spread_stalled({{16, 2.0}, {32, 1.9}}, 64));              // too few cones
  EXPECT_TRUE(spread_stalled({{16, 2.0}, {32, 1.95}}, 32));              // 1.95 > 0.95 * 2.0
  EXPECT_FALSE(spread_stalled({{32, 1.5}, {48, 1.45}, {64, 1.2}}, 64));  // 1.2 < 0.95 * 1.5
  EXPECT_TRUE(spread_stalled({{32, 1.5}, {48, 1.45}, {64, 1.45}}, 64));
  // Half as many or fewer: the latest such round counts (48 is more than half of 64 + 32).
  EXPECT_TRUE(spread_stalled({{32, 3.0}, {48, 1.0}, {96, 0.99}}, 64));
  EXPECT_FALSE(spread_stalled({{48, 1.0}, {72, 0.99}}, 64));  // no round with at most 36
}

}  // namespace
}  // namespace ricci

namespace ricci {
namespace {

// area_energy with the vertex-face incidence runs its passes in parallel: on a mesh large enough
// to be split (icosphere 7: 327680 faces), with 1, 2 and 3 threads, the value and every
// gradient entry are the same bits as the sequential passes'.
TEST(AreaEnergy, ParallelPassesGiveTheSequentialBits) {
  const Mesh mesh = make_icosphere(7);
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  ASSERT_GT(t.num_faces, 4 * 32768);
  Eigen::VectorXd area = Eigen::VectorXd::LinSpaced(t.num_faces, 1.0, 2.0);
  area /= area.sum();
  Eigen::VectorXd u(t.num_vertices);
  for (int v = 0; v < t.num_vertices; ++v) u[v] = std::sin(0.37 * v) + 0.2 * mesh.positions(v, 2);
  Eigen::VectorXd sequential_gradient;
  const double sequential = cone_steps::area_energy(t, area, u, &sequential_gradient);
  const VertexFaces incidence = vertex_faces(t);
  for (const char* threads : {"1", "2", "3"}) {
    const testing::ScopedThreads scoped(threads);
    Eigen::VectorXd gradient;
    EXPECT_EQ(cone_steps::area_energy(t, area, u, &gradient, &incidence), sequential) << threads;
    EXPECT_EQ(cone_steps::area_energy(t, area, u, nullptr, &incidence), sequential) << threads;
    ASSERT_EQ(gradient.size(), sequential_gradient.size());
    EXPECT_TRUE((gradient.array() == sequential_gradient.array()).all()) << threads;
  }
}

}  // namespace
}  // namespace ricci

namespace ricci {
namespace {

/// evaluate(k) against value and gradient through u = solve_u(k), to rounding, and the same
/// bits on 1, 2 and 3 threads.
void expect_evaluation_through_u(const ConeObjective& objective, const Eigen::VectorXd& k) {
  const Eigen::VectorXd u = objective.solve_u(k);
  Eigen::VectorXd dfdu;
  const double value = objective.value(u, k, &dfdu);
  const Eigen::VectorXd gradient = objective.gradient(u, dfdu);
  ObjectiveValue first;
  for (const char* threads : {"1", "2", "3"}) {
    const testing::ScopedThreads scoped(threads);
    const ObjectiveValue evaluated = objective.evaluate(k);
    EXPECT_NEAR(evaluated.value, value, 1e-12 * (1 + std::abs(value))) << threads;
    ASSERT_EQ(evaluated.gradient.size(), k.size());
    for (int i = 0; i < k.size(); ++i) {
      EXPECT_NEAR(evaluated.gradient[i], gradient[i], 1e-10 * (1 + gradient.cwiseAbs().maxCoeff()))
          << threads << " cone " << i;
    }
    if (first.gradient.size() == 0) {
      first = evaluated;
    } else {
      EXPECT_EQ(evaluated.value, first.value) << threads;
      EXPECT_TRUE((evaluated.gradient.array() == first.gradient.array()).all()) << threads;
    }
  }
}

// The objective evaluated on the faces (a few cones: the columns' face means, no per-vertex
// work) and on the vertices (more cones: u a block at a time) is the objective through u, and
// gives the same bits on 1, 2 and 3 threads (icosphere 6: 81920 faces, 40962 vertices, split
// between threads).
TEST(ConeObjective, EvaluationsAreTheObjectiveThroughU) {
  const Fixture fixture(make_icosphere(6), with_count(3));
  ConeSelector selector = fixture.selector();
  for (int v : {17, 5000, 23000, 39000}) add_cone(selector, v);
  const ConeObjective few = cone_objective(selector, selector.S);
  ASSERT_TRUE(few.on_faces());
  const Eigen::Vector4d k(1.1, -0.4, 2.3, 0.1 + 4 * std::numbers::pi - 3.0);
  expect_evaluation_through_u(few, k);
  for (int v : {100, 3000, 9000, 12000, 16000, 20000, 27000, 31000, 35000}) add_cone(selector, v);
  const ConeObjective many = cone_objective(selector, selector.S);
  ASSERT_FALSE(many.on_faces());
  ASSERT_TRUE(many.has_columns());
  Eigen::VectorXd k13 = Eigen::VectorXd::LinSpaced(13, -0.5, 1.2);
  k13[12] += 4 * std::numbers::pi - k13.sum();
  expect_evaluation_through_u(many, k13);
}

}  // namespace
}  // namespace ricci
