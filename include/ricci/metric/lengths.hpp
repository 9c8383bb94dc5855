#pragma once
/// \file
/// Edge lengths of a conformal structure at log radii u (THEORY.md section 2).

#include <Eigen/Core>

#include "ricci/metric/scheme.hpp"

namespace ricci {

/// What edge_lengths found: which edges have no length at u (their squared length, or the
/// hyperbolic form's sinh^2(l / 2), is not positive, or a circle packing's radius is infinite).
/// Those edges hold NaN in the output.
struct LengthsCheck {
  int invalid_edges = 0;  ///< how many edges have no length (0 for a valid metric)
  int first_edge = -1;    ///< the lowest such edge, -1 when there is none
  /// True when every edge has a length.
  bool ok() const { return invalid_edges == 0; }
};

/// Edge lengths in the structure's background (ConformalStructure::geometry):
/// euclidean_edge_lengths or hyperbolic_edge_lengths (ricci/metric/hyperbolic.hpp). The switch
/// is defined in background.cpp beside the background's other dispatches
/// (ricci/metric/background.hpp).
/// \param u #V log radii
/// \param[out] lengths #E edge lengths (resized)
/// \return the edges that have no length (none for a valid metric)
LengthsCheck edge_lengths(const Topology& topology, const ConformalStructure& structure,
                          const Eigen::VectorXd& u, Eigen::VectorXd& lengths);

/// l_ij from the unified form, l^2 = eps_i e^{2 u_i} + eps_j e^{2 u_j} + 2 eta e^{u_i + u_j}
/// (the Euclidean background, whatever structure.geometry says). Edges whose squared length is
/// not positive get NaN.
LengthsCheck euclidean_edge_lengths(const Topology& topology, const ConformalStructure& structure,
                                    const Eigen::VectorXd& u, Eigen::VectorXd& lengths);

}  // namespace ricci
