#pragma once
/// \file
/// The flow linearised at the input metric (internal): K(u) ~ K + L u, with the areas that weigh
/// u. What the cone model factorises (cones.cpp) and what the free seams' curvature is chosen
/// on (free_seams.cpp) share it, so that both read the same Laplacian.

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "numerics/detail/parallel.hpp"
#include "ricci/flow/flow_problem.hpp"
#include "ricci/metric/angles.hpp"

namespace ricci::cone_steps {

/// The linearised flow of a problem.
struct LinearFlow {
  /// dK/du at the input metric: the cotangent Laplacian of the input's intrinsic Delaunay
  /// triangulation (the flow with flips linearises to it), or the scheme's own Hessian for the
  /// circle packings (the intrinsic Delaunay one where that is indefinite).
  Eigen::SparseMatrix<double> L;
  Eigen::VectorXd curvature;  ///< #V: K of the input metric
  Eigen::VectorXd face_area;  ///< #F: each face's share of the 3D area (summing to 1)
  Eigen::VectorXd area;       ///< #V: a third of the shares of its faces (summing to 1)
  CornerAngles angles;        ///< of the input metric
};

/// Each face's share of the 3D area (summing to 1).
Eigen::VectorXd face_areas(const Mesh& mesh, const Topology& t);

/// \throw InvalidInput when the initial metric breaks a triangle inequality (`who` names the
///        caller in the message)
LinearFlow linearise_flow(const FlowProblem& problem, const char* who);

/// Loads CHOLMOD on a helper thread when the systems that follow (`rows` rows, about
/// `row_nonzeros` entries a row) will take it (SparseCholesky's Automatic choice) and it is not
/// loaded yet: the load, 3-5 ms with its BLAS, then overlaps the linearisation instead of
/// coming before the first analysis. The caller drops the task or waits for it; a load no
/// helper has started by then is left to the first analysis.
parallel::Task<void> load_cholmod_beside(int rows, int row_nonzeros);

}  // namespace ricci::cone_steps
