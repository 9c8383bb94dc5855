#pragma once
/// \file
/// The untangling energy of one face (internal to untangle_layout, separately tested): the
/// barrier chi of Garanzha et al. (2021, "Foldover-free maps in 50 lines of code") and the face
/// term (1 - theta) |J|^2 / chi(det J, eps) + theta (det J^2 + 1) / chi(det J, eps), with its
/// gradient and a positive semi-definite projection of its Hessian.

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

namespace ricci::untangle_energy {

using Vec4 = Eigen::Matrix<double, 4, 1>;
using Mat4 = Eigen::Matrix<double, 4, 4>;

/// The barrier chi(D, eps) = (D + sqrt(eps^2 + D^2)) / 2, written without cancellation for D < 0,
/// and its first two derivatives (chi' = chi / r, chi'' = eps^2 / (2 r^3), r = sqrt(eps^2 + D^2)).
struct Chi {
  double value, first, second;
};

inline Chi chi(double d, double eps) {
  const double r = std::sqrt(eps * eps + d * d);
  const double value = d >= 0 ? 0.5 * (d + r) : 0.5 * eps * eps / (r - d);
  return {value, value / r, 0.5 * eps * eps / (r * r * r)};
}

/// The face energy of J = [[a, b], [c, d]] (vec order a, b, c, d), with gradient and a positive
/// semi-definite projection of its Hessian when asked.
inline double face_energy(const Vec4& j, double eps, double theta, Vec4* gradient, Mat4* hessian) {
  const double det = j[0] * j[3] - j[1] * j[2];
  const double frobenius = j.squaredNorm();
  const Chi c = chi(det, eps);
  const double h = 1 / c.value;
  const double energy = ((1 - theta) * frobenius + theta * (det * det + 1)) * h;
  if (gradient == nullptr) return energy;
  const double h1 = -c.first * h * h;
  const double h2 = 2 * c.first * c.first * h * h * h - c.second * h * h;
  const Vec4 q(j[3], -j[2], -j[1], j[0]);  // grad det
  // Shape: |J|^2 h(det).
  *gradient = (1 - theta) * (2 * h * j + frobenius * h1 * q);
  // Area: phi(det) = (det^2 + 1) h(det).
  const double phi1 = 2 * det * h + (det * det + 1) * h1;
  const double phi2 = 2 * h + 4 * det * h1 + (det * det + 1) * h2;
  *gradient += theta * phi1 * q;
  if (hessian == nullptr) return energy;
  Mat4 p = Mat4::Zero();  // Hessian of det
  p(0, 3) = p(3, 0) = 1;
  p(1, 2) = p(2, 1) = -1;
  Mat4 hs = 2 * h * Mat4::Identity() + 2 * h1 * (j * q.transpose() + q * j.transpose()) +
            frobenius * h2 * q * q.transpose() + frobenius * h1 * p;
  Mat4 ha = phi2 * q * q.transpose() + phi1 * p;
  const Mat4 full = (1 - theta) * hs + theta * ha;
  Eigen::SelfAdjointEigenSolver<Mat4> eig(full);
  const Vec4 lambda = eig.eigenvalues().cwiseMax(0.0);
  *hessian = eig.eigenvectors() * lambda.asDiagonal() * eig.eigenvectors().transpose();
  return energy;
}

}  // namespace ricci::untangle_energy
