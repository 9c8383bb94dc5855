#include "ricci/metric/hessian.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
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
  // Built in compressed columns directly (setFromTriplets sorted 4 triplets per edge: 4 ms of
  // bunny's run). Every entry sums its terms in the order setFromTriplets took them, edge after
  // edge, (i, j), (j, i), (i, i), (j, j) within one: the same bits. Several edges may join two
  // vertices, or a vertex to itself, in an intrinsic triangulation.
  const int nv = topology.num_vertices, ne = topology.num_edges;
  struct Term {
    int row;
    double value;
  };
  std::vector<int> start(nv + 1, 0);
  for (int e = 0; e < ne; ++e) {
    const int i = topology.edge_vertices(e, 0), j = topology.edge_vertices(e, 1);
    start[i + 1] += 2, start[j + 1] += 2;
  }
  for (int v = 0; v < nv; ++v) start[v + 1] += start[v];
  // Each column's terms in the order setFromTriplets sums them.
  std::vector<Term> terms(static_cast<std::size_t>(start[nv]));
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (int e = 0; e < ne; ++e) {
    const int i = topology.edge_vertices(e, 0), j = topology.edge_vertices(e, 1);
    const double w = edge_weights[e];
    terms[fill[j]++] = {i, -w};  // (i, j)
    terms[fill[i]++] = {j, -w};  // (j, i)
    terms[fill[i]++] = {i, w};   // (i, i)
    terms[fill[j]++] = {j, w};   // (j, j)
  }
  // Per column: the terms stably sorted by row, equal rows summed in order.
  std::vector<int> entries(nv, 0);
  parallel::for_chunks(
      nv,
      [&](std::int64_t begin, std::int64_t end, int) {
        for (std::int64_t v = begin; v < end; ++v) {
          Term* first = terms.data() + start[v];
          Term* last = terms.data() + start[v + 1];
          std::stable_sort(first, last, [](const Term& a, const Term& b) { return a.row < b.row; });
          int kept = 0;
          for (Term* t = first; t != last; ++t) {
            if (kept > 0 && first[kept - 1].row == t->row) {
              first[kept - 1].value += t->value;
            } else {
              first[kept++] = *t;
            }
          }
          entries[v] = kept;
        }
      },
      parallel::kDefaultMinChunk / 4);
  std::vector<int> outer(nv + 1, 0);
  for (int v = 0; v < nv; ++v) outer[v + 1] = outer[v] + entries[v];
  std::vector<int> inner(static_cast<std::size_t>(outer[nv]));
  std::vector<double> values(static_cast<std::size_t>(outer[nv]));
  for (int v = 0; v < nv; ++v) {
    for (int k = 0; k < entries[v]; ++k) {
      inner[outer[v] + k] = terms[start[v] + k].row;
      values[outer[v] + k] = terms[start[v] + k].value;
    }
  }
  return Eigen::Map<const Eigen::SparseMatrix<double>>(nv, nv, outer[nv], outer.data(),
                                                       inner.data(), values.data());
}

}  // namespace ricci
