#include "ricci/metric/hessian.hpp"

#include <cmath>
#include <vector>

#include "numerics/detail/parallel.hpp"

namespace ricci {

void halfedge_weights(const Topology& topology, const ConformalStructure& structure,
                      const Eigen::VectorXd& u, const Eigen::VectorXd& lengths,
                      const CornerAngles& angles, Eigen::VectorXd& weights) {
  const int nf = topology.num_faces;
  weights.resize(3 * nf);
  parallel::for_chunks(
      nf,
      [&](std::int64_t begin, std::int64_t end, int) {
        for (int f = static_cast<int>(begin); f < static_cast<int>(end); ++f) {
          // power[k] = epsilon gamma^2 of the vertex at corner k; side[k] = length opposite corner
          // k. (Vertex scaling has epsilon 0 everywhere: no exponential needed for a zero power.)
          double power[3], side[3];
          for (int k = 0; k < 3; ++k) {
            const int v = topology.triangles(f, k);
            const double epsilon = structure.epsilon[v];
            power[k] = epsilon == 0 ? 0.0 : epsilon * std::exp(2.0 * u[v]);
            side[k] = lengths[topology.face_edges(f, k)];
          }
          for (int k = 0; k < 3; ++k) {
            // Halfedge opposite corner k runs from corner a = k+1 to corner b = k+2.
            const int a = (k + 1) % 3, b = (k + 2) % 3;
            const double lab = side[k];
            // Distance from the corner to the foot of the power centre on its two sides; the signed
            // distance h from the power centre to side ab follows from either end. Take the end
            // with the larger sine, so that needle triangles do not divide by a tiny number.
            const double sin_a = std::sin(angles(f, a)), sin_b = std::sin(angles(f, b));
            double h;
            if (sin_a >= sin_b) {
              const double lak = side[b];  // side opposite corner b joins a and k
              const double d_ab = (lab * lab + power[a] - power[b]) / (2 * lab);
              const double d_ak = (lak * lak + power[a] - power[k]) / (2 * lak);
              h = (d_ak - d_ab * std::cos(angles(f, a))) / sin_a;
            } else {
              const double lbk = side[a];
              const double d_ba = (lab * lab + power[b] - power[a]) / (2 * lab);
              const double d_bk = (lbk * lbk + power[b] - power[k]) / (2 * lbk);
              h = (d_bk - d_ba * std::cos(angles(f, b))) / sin_b;
            }
            weights[3 * f + k] = h / lab;
          }
        }
      },
      parallel::kDefaultMinChunk / 4);
}

void edge_weights(const Topology& topology, const Eigen::VectorXd& halfedge_weights,
                  Eigen::VectorXd& weights) {
  weights.resize(topology.num_edges);
  parallel::for_each(topology.num_edges, [&](std::int64_t e) {
    const int h0 = topology.edge_halfedges(e, 0), h1 = topology.edge_halfedges(e, 1);
    weights[e] = halfedge_weights[h0] + (h1 >= 0 ? halfedge_weights[h1] : 0.0);
  });
}

Eigen::SparseMatrix<double> curvature_hessian(const Topology& topology,
                                              const Eigen::VectorXd& edge_weights) {
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(4 * topology.num_edges);
  for (int e = 0; e < topology.num_edges; ++e) {
    const int i = topology.edge_vertices(e, 0), j = topology.edge_vertices(e, 1);
    const double w = edge_weights[e];
    triplets.emplace_back(i, j, -w);
    triplets.emplace_back(j, i, -w);
    triplets.emplace_back(i, i, w);
    triplets.emplace_back(j, j, w);
  }
  Eigen::SparseMatrix<double> L(topology.num_vertices, topology.num_vertices);
  L.setFromTriplets(triplets.begin(), triplets.end());
  return L;
}

}  // namespace ricci
