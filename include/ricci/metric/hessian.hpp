#pragma once
/// \file
/// Derivatives of the corner angles and curvatures with respect to the log radii u
/// (THEORY.md section 4). In face f = [i, j, k], with O the power centre and h_k the signed
/// distance from O to edge ij:
///     d theta_i / d u_j = d theta_j / d u_i = h_k / l_ij,
///     d theta_i / d u_i = -(h_k / l_ij + h_j / l_ik).
/// Summed over faces, dK = L du with L the weighted graph Laplacian of edge weights
/// w_ij = sum over the faces of ij of h / l_ij.

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "ricci/metric/angles.hpp"
#include "ricci/metric/scheme.hpp"

namespace ricci {

/// Per-halfedge weight h / l of halfedge h = 3 f + k (the edge opposite corner k in face f).
/// For vertex scaling this is cot(theta_k) / 2.
/// \param[out] weights 3 #F (resized)
void halfedge_weights(const Topology& topology, const ConformalStructure& structure,
                      const Eigen::VectorXd& u, const Eigen::VectorXd& lengths,
                      const CornerAngles& angles, Eigen::VectorXd& weights);

/// Edge weights w_e: the sum of the weights of the edge's halfedges. \param[out] #E
void edge_weights(const Topology& topology, const Eigen::VectorXd& halfedge_weights,
                  Eigen::VectorXd& weights);

/// The full #V by #V Hessian L = dK/du (symmetric; rows sum to zero).
Eigen::SparseMatrix<double> curvature_hessian(const Topology& topology,
                                              const Eigen::VectorXd& edge_weights);

}  // namespace ricci
