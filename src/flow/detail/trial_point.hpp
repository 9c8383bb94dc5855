#pragma once
/// \file
/// Internal to ricci_flow: evaluating the metric at log radii, and the trial point of the line
/// search, which with edge flips lives on the Delaunay triangulation at its own log radii
/// (flipped on a copy of the current triangulation, swapped in when the step is accepted).

#include <Eigen/Core>

#include "ricci/intrinsic/delaunay_flips.hpp"
#include "ricci/intrinsic/intrinsic_triangulation.hpp"
#include "ricci/mesh/topology.hpp"
#include "ricci/metric/angles.hpp"
#include "ricci/metric/scheme.hpp"

namespace ricci::flow_detail {

/// Outcome of evaluating the metric at trial log radii.
enum class Evaluation { Valid, BadLength, TriangleInequality };

/// Lengths l, angles a and curvature k of triangulation t at log radii u (no flips).
Evaluation evaluate_metric(const Topology& t, const ConformalStructure& s, const Eigen::VectorXd& u,
                           Eigen::VectorXd& l, CornerAngles& a, Eigen::VectorXd& k);
/// The same from lengths l in hand (valid ones).
Evaluation evaluate_angles(const Topology& t, Geometry geometry, const Eigen::VectorXd& l,
                           CornerAngles& a, Eigen::VectorXd& k);

/// The trial point of the line search: its log radii, lengths, angles and curvature, and the
/// triangulation they belong to when it differs from the current one.
struct TrialPoint {
  Eigen::VectorXd u, lengths, curvature;
  CornerAngles angles;
  /// The triangulation of the trial point, flipped from the current one (only when it needed
  /// flips: then `flipped`, with `flips` flips).
  IntrinsicTriangulation triangulation;
  bool flipped = false;
  int flips = 0;

  /// Evaluates the metric at u on the current triangulation (topology and structure its own);
  /// with flips, on the Delaunay triangulation at u: a copy of current flipped there when more
  /// edges fail the Delaunay test than current.blocked_flips() (a flip that cannot complete
  /// is a TriangleInequality).
  Evaluation evaluate(const IntrinsicTriangulation& current, const Topology& topology,
                      const ConformalStructure& structure, bool with_flips,
                      const DelaunayFlipOptions& flip_options);
};

}  // namespace ricci::flow_detail
