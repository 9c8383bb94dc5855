#include "flow/detail/trial_point.hpp"

#include "ricci/metric/background.hpp"
#include "ricci/metric/curvature.hpp"
#include "ricci/metric/lengths.hpp"

namespace ricci::flow_detail {

Evaluation evaluate_metric(const Topology& t, const ConformalStructure& s, const Eigen::VectorXd& u,
                           Eigen::VectorXd& l, CornerAngles& a, Eigen::VectorXd& k) {
  if (!edge_lengths(t, s, u, l).ok()) return Evaluation::BadLength;
  return evaluate_angles(t, s.geometry, l, a, k);
}

Evaluation evaluate_angles(const Topology& t, Geometry geometry, const Eigen::VectorXd& l,
                           CornerAngles& a, Eigen::VectorXd& k) {
  if (!corner_angles(t, l, a, geometry).ok()) return Evaluation::TriangleInequality;
  vertex_curvature(t, a, k);
  return Evaluation::Valid;
}

Evaluation TrialPoint::evaluate(const IntrinsicTriangulation& current, const Topology& topology,
                                const ConformalStructure& structure, bool with_flips,
                                const DelaunayFlipOptions& flip_options) {
  flipped = false;
  flips = 0;
  if (!with_flips) return evaluate_metric(topology, structure, u, lengths, angles, curvature);
  if (!edge_lengths(topology, structure, u, lengths).ok()) return Evaluation::BadLength;
  const Topology* t = &topology;
  if (count_non_delaunay_edges(topology, lengths, flip_options.tolerance, structure.geometry) >
      current.blocked_flips()) {
    triangulation = current;
    const DelaunayFlipResult r = triangulation.flip_to_delaunay(u, lengths, flip_options);
    if (!r.complete) return Evaluation::TriangleInequality;
    flipped = r.flips > 0;
    flips = r.flips;
    t = &triangulation.topology();
  }
  return evaluate_angles(*t, structure.geometry, lengths, angles, curvature);
}

}  // namespace ricci::flow_detail
