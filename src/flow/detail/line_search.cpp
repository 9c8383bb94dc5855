#include "flow/detail/line_search.hpp"

namespace ricci::flow_detail {

BacktrackingResult backtrack(const BacktrackingOptions& options, double initial, double sum_sq0,
                             const std::function<Evaluation(double alpha)>& evaluate,
                             const std::function<CurvatureErrors()>& trial_errors) {
  BacktrackingResult r;
  r.alpha = initial;
  for (;; r.alpha *= 0.5, ++r.backtracks) {
    if (r.backtracks > options.max_backtracks) return r;
    const Evaluation ev = evaluate(r.alpha);
    if (ev != Evaluation::Valid) {
      ++(ev == Evaluation::TriangleInequality ? r.triangle_failures : r.length_failures);
      continue;
    }
    if (!options.sufficient_decrease) break;
    const CurvatureErrors e = trial_errors();
    if (e.sum_sq <= (1.0 - 2.0 * options.armijo * r.alpha) * sum_sq0 ||
        e.max <= options.tolerance) {
      break;
    }
  }
  r.found = true;
  return r;
}

}  // namespace ricci::flow_detail
