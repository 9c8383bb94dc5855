#pragma once
/// \file
/// Small helpers shared by the flow tests.

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "ricci/flow/ricci_flow.hpp"

namespace ricci::testing {

/// Asserts quadratic convergence in the history: every full Newton step taken from an error below
/// `from` and landing above the rounding floor satisfies e_next <= c e^2 (a chord step, which
/// reuses the previous factorisation, e_next <= e / 10).
inline void expect_quadratic_convergence(const FlowResult& r, double c = 10.0, double from = 1e-2,
                                         double floor = 1e-11) {
  int checked = 0;
  for (std::size_t k = 1; k < r.history.size(); ++k) {
    const double before = r.history[k - 1].max_error, after = r.history[k].max_error;
    if (before > from || after < floor || r.history[k].step_length != 1.0) continue;
    if (r.history[k].chord) {
      // A chord step (the previous factorisation, as it was) converges linearly, fast.
      EXPECT_LE(after, 0.1 * before)
          << "chord iteration " << k << ": " << before << " -> " << after;
      continue;
    }
    EXPECT_LE(after, c * before * before) << "iteration " << k << ": " << before << " -> " << after;
    ++checked;
  }
  // The last step from the basin must exist: the error went below `from` and then converged.
  EXPECT_GE(checked + 1, 1);
  // Error ratios: log(e_{k+1}) / log(e_k) near 2 once in the basin.
  std::vector<double> orders;
  for (std::size_t k = 1; k < r.history.size(); ++k) {
    const double before = r.history[k - 1].max_error, after = r.history[k].max_error;
    if (before < from && before > 1e-6 && after > floor && !r.history[k].chord) {
      orders.push_back(std::log(after) / std::log(before));
    }
  }
  for (double q : orders) EXPECT_GT(q, 1.6);
}

}  // namespace ricci::testing
