#pragma once
/// \file
/// Internal: preconditioned conjugate gradients for a symmetric positive definite system whose
/// preconditioner is a factorisation of a nearby matrix (the flow's Newton steps, the cone
/// refinement's gradients): a handful of iterations where a factorisation of its own costs a
/// symbolic analysis and a numeric factorisation.

#include <Eigen/Core>

namespace ricci::numerics_detail {

/// What conjugate_gradients did.
struct ConjugateGradients {
  bool converged = false;  ///< |b - A x| <= relative_tolerance |b|
  int iterations = 0;      ///< products with A made
};

/// Solves A x = b from x = 0: `apply(p)` returns A p, `precondition(r)` an approximation of
/// A^-1 r (symmetric positive definite). Stops when the residual is at most relative_tolerance
/// |b|, after max_iterations, or when a direction has no positive curvature (A is not positive
/// definite along it, or rounding has taken over): then `converged` is false and x is where the
/// iterations stopped.
template <class Apply, class Precondition>
ConjugateGradients conjugate_gradients(const Apply& apply, const Precondition& precondition,
                                       const Eigen::VectorXd& b, double relative_tolerance,
                                       int max_iterations, Eigen::VectorXd& x) {
  ConjugateGradients result;
  x.setZero(b.size());
  Eigen::VectorXd r = b;
  Eigen::VectorXd z = precondition(r);
  Eigen::VectorXd p = z;
  double rz = r.dot(z);
  const double goal = relative_tolerance * b.norm();
  for (int k = 1; k <= max_iterations; ++k) {
    const Eigen::VectorXd Ap = apply(p);
    const double curvature_along_p = p.dot(Ap);
    if (!(curvature_along_p > 0)) return result;
    const double alpha = rz / curvature_along_p;
    x += alpha * p;
    r -= alpha * Ap;
    ++result.iterations;
    if (r.norm() <= goal) {
      result.converged = true;
      return result;
    }
    z = precondition(r);
    const double rz_next = r.dot(z);
    p = z + (rz_next / rz) * p;
    rz = rz_next;
  }
  return result;
}

}  // namespace ricci::numerics_detail
