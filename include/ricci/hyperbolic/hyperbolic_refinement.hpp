#pragma once
/// \file
/// Iterative refinement of a hyperbolic metric in extended precision. A double-precision Newton
/// flow stops where the rounding of the curvature (about 1e-15 per vertex) dominates; laid out in
/// the Poincare disk, that residual curvature turns into misclosures that grow like sinh of the
/// distance from the root, and the Fuchsian relation multiplies them by the squared norms of its
/// long words. Evaluating K in long double and correcting u with the double Hessian (whose
/// factorisation a Newton step needs anyway) brings the residual down to about 1e-18.

#include <Eigen/Core>

#include "ricci/flow/target.hpp"
#include "ricci/metric/hyperbolic.hpp"
#include "ricci/metric/scheme.hpp"

namespace ricci {

/// What refine_hyperbolic_metric returns.
struct HyperbolicRefinement {
  WideVector u;                 ///< #V refined log radii
  WideVector lengths;           ///< #E hyperbolic edge lengths at u, in long double
  double max_error_before = 0;  ///< max |K-bar - K| at the input u, evaluated in long double
  double max_error_after = 0;   ///< the same at the refined u
  int iterations = 0;           ///< corrections applied
};

/// Refines a converged hyperbolic flow: u += H^-1 (K-bar - K(u)) with K in long double and H the
/// double Hessian, until the error stops shrinking (at most max_iterations). Fixed vertices keep
/// their u.
/// \pre structure.geometry is hyperbolic and u is close to the solution (a converged flow)
/// \throw InvalidInput when the structure is not hyperbolic or the metric is not valid at u;
///        SolverError when the Hessian cannot be factorised
HyperbolicRefinement refine_hyperbolic_metric(const Topology& topology,
                                              const ConformalStructure& structure,
                                              const Target& target, const Eigen::VectorXd& u,
                                              int max_iterations = 4);

}  // namespace ricci
