#pragma once
/// \file
/// Hyperbolic background geometry (THEORY.md section 9), first pieces: the hyperbolic form of the
/// unified metric and the hyperbolic law of cosines. In constant curvature -1 a vertex carries a
/// circle of hyperbolic radius r_i, with log radius u_i = ln tanh(r_i / 2) (so u < 0), and
///     cosh l_ij = cosh r_i cosh r_j + eta_ij sinh r_i sinh r_j.

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

}  // namespace ricci
