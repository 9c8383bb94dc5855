#pragma once
/// \file
/// Intrinsic Delaunay edge flips for the vertex-scaling metric (THEORY.md section 9), in the
/// Euclidean and in the hyperbolic background.
///
/// Vertex scaling l_ij = lbar_ij exp((u_i + u_j) / 2) fails as soon as a triangle inequality
/// breaks, and strong targets break it. The cure (Gu, Luo, Sun and Wu; Springborn) keeps the
/// triangulation Delaunay for the current metric: an edge ab whose quad (a, d, b, c) is not
/// Delaunay is replaced by cd, whose length follows from Ptolemy's relation
///     l_cd = (l_ca l_bd + l_ad l_bc) / l_ab.
/// The relation commutes with the scaling (both sides pick up exp((u_c + u_d) / 2)), so the new
/// edge's constant eta_cd = l_cd^2 / (2 gamma_c gamma_d) does not depend on u: the flipped
/// triangulation carries the same discrete conformal class, exactly, and the Ricci energy stays
/// convex and twice differentiable across flips. The Delaunay test is written so that it needs no
/// triangle inequality (cos theta_c + cos theta_d >= 0 expressed through the lengths), which is
/// what lets the flips repair a metric whose triangles have already broken.
///
/// Hyperbolic background (Gu, Guo, Luo, Sun and Wu, "A discrete uniformization theorem for
/// polyhedral surfaces II", J. Differential Geom. 2018; Springborn, "Ideal hyperbolic polyhedra
/// and discrete uniformization", 2020). Vertex scaling reads sinh(l_ij / 2) = exp((u_i + u_j) / 2)
/// sinh(lbar_ij / 2), so the lambda lengths lambda = sinh(l / 2) scale exactly as Euclidean
/// lengths do, and everything above holds for them in place of l:
///  - In the hyperboloid model, 2 sinh(l / 2) is the Minkowski chord between two points of the
///    hyperboloid. Points on a hyperbolic circle lie in a spacelike plane, where the chords form
///    a Euclidean polygon inscribed in a Euclidean circle: four concyclic points satisfy
///    Ptolemy's relation for sinh(l / 2), so a Ptolemy flip of a concyclic quad is isometric.
///  - Up to a constant factor the lambda lengths are Penner's coordinates of a decorated ideal
///    triangulation (Penner, "The decorated Teichmueller space of punctured surfaces"), whose
///    Delaunay (Epstein-Penner convex hull) condition is the Euclidean delaunay_margin of the
///    lambdas. It agrees with the hyperbolic empty-circle condition and with Leibon's angle
///    condition theta_c + theta_d <= (sum of the other four angles of the quad) wherever the
///    triangles exist (tested on random quads).
///  - On a closed surface the lambdas of a Delaunay triangulation satisfy every triangle
///    inequality (a broken face would force its neighbour across the long edge to be broken
///    along a strictly longer edge), and lambdas that do give hyperbolic lengths that do (asinh
///    is subadditive): the flow with flips never meets a broken hyperbolic triangle.
///
/// The flipped triangulation is in general a Delta-complex: two edges may join the same two
/// vertices, an edge may join a vertex to itself, and a face may use a vertex twice (CAD meshes
/// with needle fans get these at once: their intrinsic Delaunay triangulation is not a simplicial
/// complex). Every array of Topology stays meaningful for such triangulations, and the metric
/// kernels (lengths, angles, curvature, Hessian) work on them unchanged; only build_topology,
/// which pairs halfedges by their end vertices, cannot rebuild one. keep_simplicial restricts
/// the flips to those that leave a simplicial complex (counting the others as blocked).

#include <vector>

#include <Eigen/Core>

#include "ricci/mesh/topology.hpp"
#include "ricci/metric/scheme.hpp"

namespace ricci {

/// cos theta_c + cos theta_d times 2, for edge ab with opposite corners c and d: the quad is
/// Delaunay when this is >= 0. Defined for any positive lengths, including triangles that break a
/// triangle inequality (their "angle" then has a cosine below -1).
/// \param ab the edge; ca, cb the other sides of the triangle with c; da, db those with d
double delaunay_margin(double ab, double ca, double cb, double da, double db);

/// The other diagonal cd of the quad of edge ab unfolded into the plane (c and d on either side
/// of ab), with the sides named as for delaunay_margin. \pre both triangles are valid
double euclidean_diagonal(double ab, double ca, double cb, double da, double db);

/// Penner's lambda length of an edge of length l (see the file comment): l in the Euclidean
/// background, sinh(l / 2) in the hyperbolic one. Vertex scaling multiplies it by
/// exp((u_i + u_j) / 2) in both.
double lambda_length(double length, Geometry geometry);

/// The edge length whose lambda length is lambda (inverse of lambda_length): lambda, or
/// 2 asinh(lambda).
double length_from_lambda(double lambda, Geometry geometry);

/// The Delaunay margin of edge ab in a hyperbolic metric: delaunay_margin of the lambda lengths
/// sinh(l / 2). Non-negative exactly when the quad is Delaunay (d outside the circumcircle of
/// a, b, c, or equivalently theta_c + theta_d <= the other four angles of the two triangles);
/// defined for any positive lengths, broken triangles included.
double hyperbolic_delaunay_margin(double ab, double ca, double cb, double da, double db);

/// The other diagonal cd of the quad of edge ab developed into the hyperbolic plane, by the
/// hyperbolic law of cosines at a in the form sinh^2(cd / 2) = sinh^2((ca - da) / 2) +
/// sinh(ca) sinh(da) sin^2(alpha / 2), alpha the angle of the quad at a (no cancellation for
/// short or nearly straight diagonals). \pre both triangles are valid hyperbolic triangles
double hyperbolic_diagonal(double ab, double ca, double cb, double da, double db);

/// The five lengths of the quad around an interior edge ab, named as for delaunay_margin: the
/// one reading of a quad that the flips, the Delaunay test and the common refinement's replay
/// share.
struct QuadLengths {
  double ab, ca, cb, da, db;
};

/// The quad of halfedge h = a -> b: its face (c, a, b) with c at corner h % 3, and its twin's
/// face (d, b, a). Inline: the Delaunay test reads it for every edge at every trial point.
/// \pre h has a twin
inline QuadLengths quad_lengths(const Topology& topology, const Eigen::VectorXd& lengths, int h) {
  const int twin = topology.halfedge_twin[h];
  const int f0 = h / 3, k0 = h % 3, f1 = twin / 3, k1 = twin % 3;
  // In face f0 the side opposite a (corner k0 + 1) is bc, the side opposite b is ca; in f1 the
  // side opposite b (corner k1 + 1) is ad, the side opposite a is db.
  return {lengths[topology.halfedge_edge[h]], lengths[topology.face_edges(f0, (k0 + 2) % 3)],
          lengths[topology.face_edges(f0, (k0 + 1) % 3)],
          lengths[topology.face_edges(f1, (k1 + 1) % 3)],
          lengths[topology.face_edges(f1, (k1 + 2) % 3)]};
}

/// The length a Ptolemy flip gives the new diagonal cd: (lambda_ca lambda_db + lambda_da
/// lambda_cb) / lambda_ab on the lambda lengths of the background (the lengths themselves in the
/// Euclidean one), turned back into a length.
double ptolemy_diagonal(const QuadLengths& quad, Geometry geometry);

/// The length an isometric flip gives the new diagonal cd: euclidean_diagonal or
/// hyperbolic_diagonal. \pre both triangles are valid in the background
double isometric_diagonal(const QuadLengths& quad, Geometry geometry);

/// Whether interior edge e can be flipped: its two faces differ and, with keep_simplicial, the
/// opposite vertices c, d are distinct and not yet joined by an edge.
bool can_flip_edge(const Topology& topology, int e, bool keep_simplicial = false);

/// Whether no face uses a vertex twice and no two edges join the same two vertices (the
/// triangulation can be written as an ordinary mesh and rebuilt by build_topology).
bool is_simplicial(const Topology& topology);

/// Flips interior edge e in place: the faces (c, a, b) and (d, b, a) become (a, d, c) and
/// (b, c, d); edge e now joins c and d (possibly c == d, a loop). Face and edge indices are kept
/// (edge e is reused), so per-face and per-edge arrays stay aligned; halfedge arrays, face_edges,
/// edge_vertices, edge_halfedges and vertex_degree are updated. Boundaries, components and the
/// Euler characteristic do not change. \pre can_flip_edge(topology, e)
void flip_edge(Topology& topology, int e);

/// Flips interior edge e of a vertex-scaling metric at log radii u: the new edge's length by
/// Ptolemy's relation from the current lengths (on the lambda lengths sinh(l / 2) in the
/// hyperbolic background), its eta so that edge_lengths reproduces it.
/// \pre can_flip_edge(topology, e); lengths are l(u) of the current triangulation
/// \return the new length
double ptolemy_flip(Topology& topology, ConformalStructure& structure, const Eigen::VectorXd& u,
                    Eigen::VectorXd& lengths, int e);

/// Options of flip_to_delaunay.
struct DelaunayFlipOptions {
  /// An edge is flipped when its delaunay_margin is below -tolerance; the slack keeps
  /// cocircular quads (margin 0 up to rounding) from flipping back and forth.
  double tolerance = 1e-12;
  int max_flips = 0;  ///< safety stop; 0: 50 #E
  /// Skip flips that would leave a simplicial complex (see the file comment).
  bool keep_simplicial = false;
  /// Flip isometrically (the new edge is the diagonal of the quad developed into the plane, or
  /// into the hyperbolic plane: the same surface, retriangulated) instead of by Ptolemy's
  /// relation (the same conformal class).
  bool isometric = false;
};

/// What flip_to_delaunay did.
struct DelaunayFlipResult {
  int flips = 0;  ///< edges flipped
  /// The edges flipped, in order: flip_edge applied to them one after the other on the input
  /// triangulation reproduces the output (how the intrinsic triangulation corresponds to the
  /// input one: ricci/intrinsic/intrinsic_triangulation.hpp).
  std::vector<int> flipped_edges;
  int blocked = 0;       ///< non-Delaunay edges left unflipped (keep_simplicial, or an edge
                         ///< inside a single self-glued face)
  bool complete = true;  ///< false when max_flips stopped the algorithm
};

/// Flips a vertex-scaling metric (epsilon = 0 at every vertex) to an intrinsic Delaunay
/// triangulation at log radii u, in the background geometry of the structure (the Delaunay test,
/// Ptolemy's relation and the isometric diagonal are those of structure.geometry). Edges are
/// visited in index order and re-queued when a neighbouring flip changes their quad, so the
/// result is deterministic.
/// \param[in,out] topology the triangulation, flipped in place
/// \param[in,out] structure its eta changes on flipped edges (epsilon must be zero)
/// \param[in,out] lengths #E current lengths l(u), updated on flipped edges
/// \throw InvalidInput when the structure is not vertex scaling
DelaunayFlipResult flip_to_delaunay(Topology& topology, ConformalStructure& structure,
                                    const Eigen::VectorXd& u, Eigen::VectorXd& lengths,
                                    const DelaunayFlipOptions& options = {});

/// Number of interior edges whose Delaunay margin (delaunay_margin, or
/// hyperbolic_delaunay_margin) is below -tolerance at these lengths.
int count_non_delaunay_edges(const Topology& topology, const Eigen::VectorXd& lengths,
                             double tolerance = 1e-12, Geometry geometry = Geometry::Euclidean);

}  // namespace ricci
