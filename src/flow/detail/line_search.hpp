#pragma once
/// \file
/// Internal to ricci_flow: the backtracking of the line search along a step direction.

#include <functional>

#include "flow/detail/stopping.hpp"
#include "flow/detail/trial_point.hpp"

namespace ricci::flow_detail {

/// How the backtracking accepts a step.
struct BacktrackingOptions {
  int max_backtracks = 50;  ///< halvings before it gives up
  /// Newton: accept only a sufficient decrease of |K-bar - K|^2 (Armijo) or an error within
  /// the tolerance; otherwise (the gradient flow) the first step that evaluates.
  bool sufficient_decrease = true;
  double armijo = 1e-4;      ///< the sufficient decrease: by 2 armijo alpha of |K-bar - K|^2
  double tolerance = 1e-10;  ///< an error at most this is accepted as it is
};

/// What the backtracking found.
struct BacktrackingResult {
  bool found = false;         ///< a step was accepted (the trial point holds it)
  double alpha = 0;           ///< the accepted step length
  int backtracks = 0;         ///< halvings made (max_backtracks + 1 when none was found)
  int triangle_failures = 0;  ///< trials that broke a triangle inequality
  int length_failures = 0;    ///< trials with a non-positive or overflowing edge length
};

/// Tries alpha = initial, initial / 2, ...: evaluate(alpha) evaluates the trial point at step
/// alpha (a step that breaks a triangle or a length is shortened, never accepted) and
/// trial_errors() gives its curvature errors (asked only for a sufficient decrease, against
/// sum_sq0, the current sum of squares).
BacktrackingResult backtrack(const BacktrackingOptions& options, double initial, double sum_sq0,
                             const std::function<Evaluation(double alpha)>& evaluate,
                             const std::function<CurvatureErrors()>& trial_errors);

}  // namespace ricci::flow_detail
