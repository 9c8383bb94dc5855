#pragma once
/// \file
/// Edge lengths of a conformal structure at log radii u (THEORY.md section 2).

#include <Eigen/Core>

#include "ricci/metric/scheme.hpp"

namespace ricci {

/// Computes l_ij from the unified form. Edges whose squared length is not positive get NaN.
/// \param u #V log radii
/// \param[out] lengths #E edge lengths (resized)
/// \return number of edges whose squared length is not positive (0 for a valid metric)
int edge_lengths(const Topology& topology, const ConformalStructure& structure,
                 const Eigen::VectorXd& u, Eigen::VectorXd& lengths);

}  // namespace ricci
