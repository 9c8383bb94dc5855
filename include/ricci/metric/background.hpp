#pragma once
/// \file
/// The dispatch on the background geometry (ricci/metric/geometry.hpp) of everything the flow
/// computes from a metric: one switch each, all defined in background.cpp. Lengths and angles
/// keep their declarations where callers look for them (edge_lengths in lengths.hpp on
/// ConformalStructure::geometry, the Geometry overload of corner_angles in angles.hpp); the
/// Hessian's terms and Gauss-Bonnet are declared here. What a caller decides by the background
/// (the gauge, the form of Gauss-Bonnet) it reads from geometry_traits instead of testing the
/// enum. Adding a background means a row of kGeometryTraits, its formulas in a file of its own
/// (as hyperbolic.hpp), and a case in each switch of background.cpp; the Delaunay flips' Ptolemy
/// quantity (lambda_length in delaunay_flips.hpp) is the one other place that names it.

#include <Eigen/Core>

#include "ricci/metric/angles.hpp"
#include "ricci/metric/geometry.hpp"
#include "ricci/metric/scheme.hpp"

namespace ricci {

/// The terms the flow assembles the Hessian H = dK/du from, at one metric.
///   Euclidean: halfedge_weights (hessian.hpp), no diagonal term;
///   hyperbolic: hyperbolic_hessian_terms (hyperbolic.hpp), and the per-vertex sum of its corner
///   diagonal, which makes H positive definite.
/// \param[out] halfedge_weights 3 #F (resized)
/// \param[out] corner_diagonal 3 #F (resized; empty when the background has none)
/// \param[out] vertex_diagonal #V (resized; empty when the background has none)
void hessian_terms(const Topology& topology, const ConformalStructure& structure,
                   const Eigen::VectorXd& u, const Eigen::VectorXd& lengths,
                   const CornerAngles& angles, Eigen::VectorXd& halfedge_weights,
                   Eigen::VectorXd& corner_diagonal, Eigen::VectorXd& vertex_diagonal);

/// Total area of the metric where Gauss-Bonnet needs it (hyperbolic: pi minus each triangle's
/// angle sum, summed); 0 in the Euclidean background.
double gauss_bonnet_area(Geometry geometry, const CornerAngles& angles);

/// The Gauss-Bonnet defect of the background, relative to the size of the sum:
/// |sum K - area - 2 pi chi| / max(1, 2 pi #V), with area 0 in the Euclidean background
/// (curvature.hpp's gauss_bonnet_relative_error and hyperbolic_gauss_bonnet_relative_error).
double gauss_bonnet_relative_error(Geometry geometry, const Topology& topology,
                                   const Eigen::VectorXd& curvature, double area);

}  // namespace ricci
