#include "ricci/metric/lengths.hpp"

#include <cmath>
#include <limits>

#include "numerics/detail/parallel.hpp"

namespace ricci {

LengthsCheck euclidean_edge_lengths(const Topology& topology, const ConformalStructure& structure,
                                    const Eigen::VectorXd& u, Eigen::VectorXd& lengths) {
  const int ne = topology.num_edges;
  lengths.resize(ne);
  // e^u once per vertex (the same values an evaluation per edge end would give).
  Eigen::VectorXd gamma(u.size());
  parallel::for_each(u.size(), [&](std::int64_t v) { gamma[v] = std::exp(u[v]); });
  const std::int64_t invalid = parallel::count_if(ne, [&](std::int64_t e) {
    const int i = topology.edge_vertices(e, 0);
    const int j = topology.edge_vertices(e, 1);
    const double gi = gamma[i];
    const double gj = gamma[j];
    const double squared = structure.epsilon[i] * gi * gi + structure.epsilon[j] * gj * gj +
                           2.0 * structure.eta[e] * gi * gj;
    if (squared > 0 && std::isfinite(squared)) {
      lengths[e] = std::sqrt(squared);
      return false;
    }
    lengths[e] = std::numeric_limits<double>::quiet_NaN();
    return true;
  });
  LengthsCheck check;
  check.invalid_edges = static_cast<int>(invalid);
  if (invalid > 0) {
    // Found after the parallel count so that it is the lowest such edge on any thread count.
    for (int e = 0; e < ne && check.first_edge < 0; ++e) {
      if (std::isnan(lengths[e])) check.first_edge = e;
    }
  }
  return check;
}

}  // namespace ricci
