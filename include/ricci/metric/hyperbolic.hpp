#pragma once
/// \file
/// Hyperbolic background geometry (THEORY.md section 9), first pieces: the hyperbolic form of the
/// unified metric and the hyperbolic law of cosines. In constant curvature -1 a vertex carries a
/// circle of hyperbolic radius r_i, with log radius u_i = ln tanh(r_i / 2) (so u < 0), and
///     cosh l_ij = cosh r_i cosh r_j + eta_ij sinh r_i sinh r_j.

#include <Eigen/Core>

#include "ricci/metric/angles.hpp"
#include "ricci/metric/lengths.hpp"
#include "ricci/metric/scheme.hpp"

namespace ricci {

/// Hyperbolic radius from the log radius u = ln tanh(r / 2) (u < 0): r = 2 atanh(e^u).
/// Returns NaN for u >= 0 (no hyperbolic circle has tanh(r / 2) >= 1).
double hyperbolic_radius(double u);

/// Log radius u = ln tanh(r / 2) of a hyperbolic radius r > 0.
double hyperbolic_log_radius(double r);

/// Edge length of the hyperbolic unified form: acosh(cosh r_i cosh r_j + eta sinh r_i sinh r_j).
/// Returns NaN when the argument of acosh falls below 1 (no such edge).
double hyperbolic_edge_length(double r_i, double r_j, double eta);

/// Angle opposite side a of a hyperbolic triangle with sides a, b, c, by the half-angle form of
/// the hyperbolic law of cosines,
///     tan(A / 2) = sqrt(sinh(s - b) sinh(s - c) / (sinh s sinh(s - a))),  s = (a + b + c) / 2,
/// which keeps full relative accuracy for tiny and near-pi angles (acos of
/// (cosh b cosh c - cosh a) / (sinh b sinh c) loses it). NaN when a triangle inequality fails or
/// a side is not positive.
double hyperbolic_angle_from_lengths(double a, double b, double c);

/// Hyperbolic edge lengths of a structure at log radii u (ConformalStructure's hyperbolic form),
/// computed as l = 2 asinh(sqrt(q)) with q = sinh^2(l / 2), accurate for short edges.
/// \param[out] lengths #E (resized); NaN where q is not positive or a circle packing's radius is
///        infinite (eps t^2 >= 1)
/// \return those edges (none for a valid metric)
LengthsCheck hyperbolic_edge_lengths(const Topology& topology, const ConformalStructure& structure,
                                     const Eigen::VectorXd& u, Eigen::VectorXd& lengths);

/// Corner angles of hyperbolic triangles by the half-angle form of the hyperbolic law of cosines,
/// tan(theta_k / 2) = sqrt(sinh(s - l_{k+1}) sinh(s - l_{k+2}) / (sinh s sinh(s - l_k))).
/// \param[out] angles #F by 3 (resized)
/// \return the first face that breaks a triangle inequality (its angles are NaN), if any
AnglesCheck hyperbolic_corner_angles(const Topology& topology, const Eigen::VectorXd& lengths,
                                     CornerAngles& angles);

/// Vectors and corner angles in long double (x87 extended precision on x86-64; plain double
/// elsewhere), for the extended-precision refinement and layout of a hyperbolic metric.
using WideVector = Eigen::Matrix<long double, Eigen::Dynamic, 1>;
using WideAngles = Eigen::Matrix<long double, Eigen::Dynamic, 3>;

/// hyperbolic_edge_lengths in long double (the same formula, evaluated with more bits).
LengthsCheck hyperbolic_edge_lengths_wide(const Topology& topology,
                                          const ConformalStructure& structure, const WideVector& u,
                                          WideVector& lengths);

/// Corner angles of hyperbolic triangles in long double (as hyperbolic_corner_angles). \return the
/// first face that breaks a triangle inequality, if any
AnglesCheck hyperbolic_corner_angles_wide(const Topology& topology, const WideVector& lengths,
                                          WideAngles& angles);

/// d l_ij / d u_i and d l_ij / d u_j of one edge of the hyperbolic form.
Eigen::Vector2d hyperbolic_length_derivatives(double u_i, double u_j, double epsilon_i,
                                              double epsilon_j, double eta, double length);

/// d theta_a / d u_b in one face (a, b its corners 0..2), by the chain rule through the edge
/// lengths: d theta_i / d l_i = sinh l_i / (sinh l_j sinh l_k sin theta_i) and
/// d theta_i / d l_j = -(d theta_i / d l_i) cos theta_k (l_i is opposite corner i). The matrix is
/// symmetric (the Ricci energy exists) and, for the schemes here, negative definite: the
/// hyperbolic energy is strictly convex, so no gauge is needed.
Eigen::Matrix3d hyperbolic_face_jacobian(const Topology& topology,
                                         const ConformalStructure& structure,
                                         const Eigen::VectorXd& u, const Eigen::VectorXd& lengths,
                                         const CornerAngles& angles, int face);

/// The hyperbolic Hessian H = dK/du in the shape the flow assembles:
///     H_ij = -(sum of the weights of the halfedges of edge ij)   (i != j),
///     H_ii = sum over j of the edge weights + sum of corner_diagonal over i's corners,
/// with weight(3 f + k) = d theta_{k+1} / d u_{k+2} (symmetrised) and corner_diagonal(3 f + k) =
/// -(row sum of face f's Jacobian at corner k) > 0: the part of the diagonal that makes H
/// positive definite (it is 0 in the Euclidean background, where K is invariant under u += c).
/// \param[out] weights 3 #F (resized) \param[out] corner_diagonal 3 #F (resized)
void hyperbolic_hessian_terms(const Topology& topology, const ConformalStructure& structure,
                              const Eigen::VectorXd& u, const Eigen::VectorXd& lengths,
                              const CornerAngles& angles, Eigen::VectorXd& weights,
                              Eigen::VectorXd& corner_diagonal);

/// Area of every hyperbolic triangle, pi minus its angle sum, summed (compensated).
double hyperbolic_total_area(const CornerAngles& angles);

/// Options of make_conformal_structure in the hyperbolic background: the scale of the input
/// lengths (StructureOptions::hyperbolic_length_scale, 0 = automatic) as the function resolves it.
double hyperbolic_length_scale(const Topology& topology, const Eigen::VectorXd& input_lengths,
                               double requested);

/// make_conformal_structure for options.geometry == Hyperbolic: lengths L = scale * lbar.
/// Circle packings take their radii from the Euclidean fit of L (small triangles are nearly
/// Euclidean) and then eta from the hyperbolic cosine law, clamped to [cos Phi_max, 1] for
/// Thurston; vertex scaling has eta = sinh^2(L / 2) / 2 at u = 0. The fit errors compare the
/// hyperbolic lengths with L.
/// \throw InvalidInput for the virtual-radius scheme, whose hyperbolic energy is not convex
StructureResult make_hyperbolic_structure(const Topology& topology,
                                          const Eigen::VectorXd& input_lengths,
                                          const StructureOptions& options);

}  // namespace ricci
