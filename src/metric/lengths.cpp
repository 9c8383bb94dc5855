#include "ricci/metric/lengths.hpp"

#include <cmath>
#include <limits>

#include "ricci/metric/hyperbolic.hpp"

namespace ricci {

int edge_lengths(const Topology& topology, const ConformalStructure& structure,
                 const Eigen::VectorXd& u, Eigen::VectorXd& lengths) {
  if (structure.geometry == Geometry::Hyperbolic) {
    return hyperbolic_edge_lengths(topology, structure, u, lengths);
  }
  const int ne = topology.num_edges;
  lengths.resize(ne);
  int invalid = 0;
  for (int e = 0; e < ne; ++e) {
    const int i = topology.edge_vertices(e, 0);
    const int j = topology.edge_vertices(e, 1);
    const double gi = std::exp(u[i]);
    const double gj = std::exp(u[j]);
    const double squared = structure.epsilon[i] * gi * gi + structure.epsilon[j] * gj * gj +
                           2.0 * structure.eta[e] * gi * gj;
    if (squared > 0 && std::isfinite(squared)) {
      lengths[e] = std::sqrt(squared);
    } else {
      lengths[e] = std::numeric_limits<double>::quiet_NaN();
      ++invalid;
    }
  }
  return invalid;
}

}  // namespace ricci
