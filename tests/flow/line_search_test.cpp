// The backtracking of ricci_flow's line search (src/flow/detail/line_search.hpp), on made-up
// trial points: which step it accepts and what it counts.

#include "flow/detail/line_search.hpp"

#include <vector>

#include <gtest/gtest.h>

namespace ricci {
namespace {

using flow_detail::backtrack;
using flow_detail::BacktrackingOptions;
using flow_detail::BacktrackingResult;
using flow_detail::CurvatureErrors;
using flow_detail::Evaluation;

TEST(Backtrack, HalvesPastBrokenTrialsAndCountsThem) {
  BacktrackingOptions o;
  o.sufficient_decrease = false;  // the gradient flow: the first valid step
  std::vector<double> tried;
  const BacktrackingResult r = backtrack(
      o, 1.0, 1.0,
      [&](double alpha) {
        tried.push_back(alpha);
        if (alpha > 0.3) return Evaluation::TriangleInequality;
        if (alpha > 0.2) return Evaluation::BadLength;
        return Evaluation::Valid;
      },
      [] {
        ADD_FAILURE() << "the gradient flow asks for no errors";
        return CurvatureErrors{};
      });
  EXPECT_TRUE(r.found);
  EXPECT_EQ(r.alpha, 0.125);
  EXPECT_EQ(tried, (std::vector<double>{1.0, 0.5, 0.25, 0.125}));
  EXPECT_EQ(r.backtracks, 3);
  EXPECT_EQ(r.triangle_failures, 2);
  EXPECT_EQ(r.length_failures, 1);
}

TEST(Backtrack, NewtonAsksForASufficientDecrease) {
  BacktrackingOptions o;
  o.armijo = 0.25;
  o.tolerance = 1e-10;
  // sum_sq(alpha) = 1 - alpha / 4 (a poor direction): Armijo asks for 1 - alpha / 2, never met
  // above zero; with sum_sq = 1 - alpha it is met at once.
  double slope = 0.25;
  auto evaluate = [&](double) { return Evaluation::Valid; };
  double last_alpha = 0;
  auto errors = [&] { return CurvatureErrors{1.0, 1.0 - slope * last_alpha, 1}; };
  auto tracked = [&](double alpha) {
    last_alpha = alpha;
    return evaluate(alpha);
  };
  o.max_backtracks = 4;
  BacktrackingResult r = backtrack(o, 1.0, 1.0, tracked, errors);
  EXPECT_FALSE(r.found);
  EXPECT_EQ(r.backtracks, 5);  // max_backtracks + 1: the halving that gave up
  slope = 1.0;
  r = backtrack(o, 1.0, 1.0, tracked, errors);
  EXPECT_TRUE(r.found);
  EXPECT_EQ(r.alpha, 1.0);
  EXPECT_EQ(r.backtracks, 0);
}

TEST(Backtrack, AnErrorWithinTheToleranceIsAccepted) {
  BacktrackingOptions o;
  o.tolerance = 1e-10;
  const BacktrackingResult r = backtrack(
      o, 1.0, 1e-24, [](double) { return Evaluation::Valid; },
      [] {
        return CurvatureErrors{5e-11, 2e-21, 1};
      });  // no decrease, but converged
  EXPECT_TRUE(r.found);
  EXPECT_EQ(r.alpha, 1.0);
}

}  // namespace
}  // namespace ricci
