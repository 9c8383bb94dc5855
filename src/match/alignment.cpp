#include "ricci/match/alignment.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <string>

#include <Eigen/Dense>

#include "ricci/errors.hpp"
#include "ricci/match/domain_locator.hpp"

namespace ricci {
namespace {

using cd = std::complex<double>;
constexpr double kTwoPi = 2 * std::numbers::pi;

// --- The sphere as the Riemann sphere --------------------------------------------------------

// Homogeneous stereographic coordinates (z1 : z2), z = z1 / z2 = (x + i y) / (1 - z), from
// whichever of the two equal quotients is far from 0 / 0.
Eigen::Vector2cd to_homogeneous(const Eigen::Vector3d& x) {
  if (x.z() <= 0) return {cd(x.x(), x.y()), cd(1 - x.z(), 0)};
  return {cd(1 + x.z(), 0), cd(x.x(), -x.y())};
}

Eigen::Vector3d from_homogeneous(const Eigen::Vector2cd& w) {
  const double n1 = std::norm(w(0)), n2 = std::norm(w(1));
  const cd p = 2.0 * w(0) * std::conj(w(1));
  return Eigen::Vector3d(p.real(), p.imag(), n1 - n2) / (n1 + n2);
}

Eigen::Matrix2cd unit_determinant(const Eigen::Matrix2cd& m) {
  return m / std::sqrt(m.determinant());
}

// --- Levenberg-Marquardt on a few parameters, numerical Jacobian ----------------------------

Eigen::VectorXd levenberg_marquardt(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f,
                                    Eigen::VectorXd x, int iterations = 100) {
  double mu = 1e-3;
  Eigen::VectorXd r = f(x);
  double cost = r.squaredNorm();
  for (int it = 0; it < iterations && cost > 1e-30; ++it) {
    Eigen::MatrixXd j(r.size(), x.size());
    for (Eigen::Index k = 0; k < x.size(); ++k) {
      const double h = 1e-7 * std::max(1.0, std::abs(x(k)));
      Eigen::VectorXd xp = x, xm = x;
      xp(k) += h;
      xm(k) -= h;
      j.col(k) = (f(xp) - f(xm)) / (2 * h);
    }
    const Eigen::MatrixXd jtj = j.transpose() * j;
    const Eigen::VectorXd g = j.transpose() * r;
    bool improved = false;
    for (int tries = 0; tries < 20; ++tries) {
      Eigen::MatrixXd a = jtj;
      a.diagonal().array() += mu * (1 + jtj.diagonal().array());
      const Eigen::VectorXd step = a.ldlt().solve(-g);
      const Eigen::VectorXd trial = x + step;
      const Eigen::VectorXd rt = f(trial);
      const double ct = rt.squaredNorm();
      if (std::isfinite(ct) && ct < cost) {
        x = trial;
        r = rt;
        const bool tiny = step.norm() < 1e-15 * (1 + x.norm()) || cost - ct < 1e-16 * cost;
        cost = ct;
        mu = std::max(mu / 4, 1e-12);
        improved = true;
        if (tiny) return x;
        break;
      }
      mu *= 8;
    }
    if (!improved) break;
  }
  return x;
}

// --- Samples of A and fields of B ---------------------------------------------------------------

struct Samples {
  std::vector<int> vertex;
  Eigen::VectorXd weight, factor;
};

Samples sample_vertices(const CanonicalDomain& a, const Triangles& triangles, int max_samples) {
  const Eigen::Index nv = a.points.rows();
  Eigen::VectorXd vertex_area = Eigen::VectorXd::Zero(nv);
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    for (int k = 0; k < 3; ++k) vertex_area(triangles(f, k)) += a.area_share(f) / 3;
  }
  const Eigen::Index stride =
      std::max<Eigen::Index>(1, (nv + max_samples - 1) / std::max(1, max_samples));
  Samples s;
  for (Eigen::Index v = 0; v < nv; v += stride) {
    if (vertex_area(v) > 0) s.vertex.push_back(static_cast<int>(v));
  }
  s.weight.resize(static_cast<Eigen::Index>(s.vertex.size()));
  s.factor.resize(s.weight.size());
  for (std::size_t i = 0; i < s.vertex.size(); ++i) {
    s.weight(static_cast<Eigen::Index>(i)) = vertex_area(s.vertex[i]);
    s.factor(static_cast<Eigen::Index>(i)) = a.log_area_factor(s.vertex[i]);
  }
  s.weight /= s.weight.sum();
  return s;
}

// Every k-th sample, at most `count` (weights renormalised).
Samples subsample(const Samples& s, int count) {
  const std::size_t stride =
      std::max<std::size_t>(1, (s.vertex.size() + count - 1) / static_cast<std::size_t>(count));
  Samples few;
  for (std::size_t i = 0; i < s.vertex.size(); i += stride) few.vertex.push_back(s.vertex[i]);
  few.weight.resize(static_cast<Eigen::Index>(few.vertex.size()));
  few.factor.resize(few.weight.size());
  for (std::size_t i = 0, k = 0; i < s.vertex.size(); i += stride, ++k) {
    few.weight(static_cast<Eigen::Index>(k)) = s.weight(static_cast<Eigen::Index>(i));
    few.factor(static_cast<Eigen::Index>(k)) = s.factor(static_cast<Eigen::Index>(i));
  }
  few.weight /= few.weight.sum();
  return few;
}

// A scalar field tabulated on a periodic or clamped rectangular grid, read bilinearly.
struct Grid {
  int nu = 1, nv = 1;
  bool periodic_u = false, periodic_v = false;
  Eigen::MatrixXd value;                 // nu by nv
  double at(double u, double v) const {  // u, v in grid units
    const auto index = [](double x, int n, bool periodic, int& i0, int& i1, double& t) {
      if (periodic) {
        x -= n * std::floor(x / n);
        i0 = std::min(static_cast<int>(x), n - 1);
        i1 = (i0 + 1) % n;
      } else {
        x = std::clamp(x, 0.0, n - 1.0);
        i0 = std::min(static_cast<int>(x), n - 2 < 0 ? 0 : n - 2);
        i1 = std::min(i0 + 1, n - 1);
      }
      t = x - i0;
    };
    int u0, u1, v0, v1;
    double tu, tv;
    index(u, nu, periodic_u, u0, u1, tu);
    index(v, nv, periodic_v, v0, v1, tv);
    return (1 - tu) * ((1 - tv) * value(u0, v0) + tv * value(u0, v1)) +
           tu * ((1 - tv) * value(u1, v0) + tv * value(u1, v1));
  }
};

double read_factor(const DomainLocator& locator, const Eigen::Vector3d& p) {
  const FaceLocation at = locator.locate(p);
  if (at.face < 0) return 0;
  return locator.interpolate(locator.domain().log_area_factor, at)(0);
}

// B's conformal factor on the sphere, on a latitude-longitude grid.
struct SphereField {
  Grid grid;
  explicit SphereField(const DomainLocator& b) {
    grid.nu = 181;
    grid.nv = 360;
    grid.periodic_v = true;
    grid.value.resize(grid.nu, grid.nv);
    for (int i = 0; i < grid.nu; ++i) {
      const double theta = std::numbers::pi * i / (grid.nu - 1);
      for (int j = 0; j < grid.nv; ++j) {
        const double phi = kTwoPi * j / grid.nv;
        grid.value(i, j) = read_factor(
            b, {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)});
      }
    }
  }
  double at(const Eigen::Vector3d& x) const {
    const double theta = std::acos(std::clamp(x.z() / x.norm(), -1.0, 1.0));
    const double phi = std::atan2(x.y(), x.x());
    return grid.at(theta / std::numbers::pi * (grid.nu - 1), phi / kTwoPi * grid.nv);
  }
};

double weighted_mismatch(const Samples& s, const std::function<double(int)>& factor_b_at) {
  double sum = 0;
  for (Eigen::Index i = 0; i < s.weight.size(); ++i) {
    const double d = s.factor(i) - factor_b_at(static_cast<int>(i));
    sum += s.weight(i) * d * d;
  }
  return sum;
}

// The residuals whose squared norm is weighted_mismatch, for Levenberg-Marquardt.
Eigen::VectorXd weighted_residuals(const Samples& s,
                                   const std::function<double(int)>& factor_b_at) {
  Eigen::VectorXd out(s.weight.size());
  for (Eigen::Index i = 0; i < out.size(); ++i) {
    out(i) = std::sqrt(s.weight(i)) * (s.factor(i) - factor_b_at(static_cast<int>(i)));
  }
  return out;
}

// The rotation by |w| about w (the exponential map).
Eigen::Matrix3d rotation_of(const Eigen::Vector3d& w) {
  const double angle = w.norm();
  if (!(angle > 0)) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
}

Eigen::Matrix3d axis_rotation(int axis, double angle) {
  return Eigen::AngleAxisd(angle, Eigen::Vector3d::Unit(axis)).toRotationMatrix();
}

// Coordinate descent over small rotations about the three axes: steps from `largest` halving
// to `smallest`, at most `moves` accepted moves per step size (a rugged, interpolated cost
// would otherwise creep on at the finest steps).
template <class Cost>
void descend_rotation(Eigen::Matrix3d& r, double& value, const Cost& cost, double largest,
                      double smallest, int moves) {
  for (double step = largest; step > smallest; step /= 2) {
    for (int move = 0; move < moves; ++move) {
      bool moved = false;
      for (int axis = 0; axis < 3; ++axis) {
        for (double sign : {-1.0, 1.0}) {
          const Eigen::Matrix3d trial = axis_rotation(axis, sign * step) * r;
          const double ct = cost(trial);
          if (ct < value) {
            value = ct;
            r = trial;
            moved = true;
          }
        }
      }
      if (!moved) break;
    }
  }
}

// The rotation R minimising the conformal factors' mismatch, a(x) against b(R x): 4096
// rotations and the identity on B's table, the best 9 refined there, the best of those polished
// on B's factor read exactly (a surface matched to itself then gets the identity to rounding).
Eigen::Matrix3d best_rotation(const CanonicalDomain& a, const Samples& s, const SphereField& field,
                              const DomainLocator& locator_b) {
  // The table's cost on at most 1000 samples (4096 rotations), the exact one likewise.
  const Samples coarse = subsample(s, 1000);
  const auto cost = [&](const Eigen::Matrix3d& r) {
    return weighted_mismatch(coarse, [&](int i) {
      return field.at(r * a.points.row(coarse.vertex[static_cast<std::size_t>(i)]).transpose());
    });
  };
  const Samples& few = coarse;
  const auto exact_cost = [&](const Eigen::Matrix3d& r) {
    return weighted_mismatch(few, [&](int i) {
      return read_factor(locator_b,
                         r * a.points.row(few.vertex[static_cast<std::size_t>(i)]).transpose());
    });
  };
  std::mt19937 generator(20261128);
  const auto uniform = [&] { return (generator() + 0.5) / 4294967296.0; };
  std::vector<std::pair<double, Eigen::Matrix3d>> candidates;
  for (int k = 0; k < 4096; ++k) {
    // Shoemake's uniform random unit quaternion.
    const double u1 = uniform(), u2 = uniform(), u3 = uniform();
    const Eigen::Quaterniond q(
        std::sqrt(u1) * std::cos(kTwoPi * u3), std::sqrt(1 - u1) * std::sin(kTwoPi * u2),
        std::sqrt(1 - u1) * std::cos(kTwoPi * u2), std::sqrt(u1) * std::sin(kTwoPi * u3));
    const Eigen::Matrix3d r = q.toRotationMatrix();
    candidates.emplace_back(cost(r), r);
  }
  std::sort(candidates.begin(), candidates.end(),
            [](const auto& x, const auto& y) { return x.first < y.first; });
  candidates.resize(std::min<std::size_t>(8, candidates.size()));
  candidates.emplace_back(cost(Eigen::Matrix3d::Identity()), Eigen::Matrix3d::Identity());
  double best_cost = std::numeric_limits<double>::infinity();
  Eigen::Matrix3d best = Eigen::Matrix3d::Identity();
  std::vector<std::pair<double, Eigen::Matrix3d>> refined;
  for (auto [value, r] : candidates) {
    descend_rotation(r, value, cost, 0.1, 1e-3, 8);
    refined.emplace_back(value, r);
    if (value < best_cost) {
      best_cost = value;
      best = r;
    }
  }
  (void)best_cost;
  // The best 4 on the table, and the identity, polished on B's factor read exactly (the table's
  // interpolation can misorder rotations where the factor is steep: a rabbit's ears).
  std::sort(refined.begin(), refined.end(),
            [](const auto& x, const auto& y) { return x.first < y.first; });
  refined.resize(std::min<std::size_t>(4, refined.size()));
  refined.emplace_back(0.0, Eigen::Matrix3d::Identity());
  for (auto& [value, r] : refined) value = exact_cost(r);
  std::sort(refined.begin(), refined.end(),
            [](const auto& x, const auto& y) { return x.first < y.first; });
  // Then Levenberg-Marquardt on the residuals, over rotations exp(w) R: B's exact factor is
  // piecewise linear, and steps along the three axes alone can stall in a valley that runs across
  // them (spot against its rotated copy stopped at a mismatch of 0.035 instead of 1e-12 where
  // BLAS's kernels rounded otherwise).
  const auto residuals_from = [&](const Eigen::Matrix3d& r0) {
    return [&, r0](const Eigen::VectorXd& w) {
      const Eigen::Matrix3d r = rotation_of(w) * r0;
      return weighted_residuals(few, [&](int i) {
        return read_factor(locator_b,
                           r * a.points.row(few.vertex[static_cast<std::size_t>(i)]).transpose());
      });
    };
  };
  // The two best starts only: each polish reads the factor a few hundred times.
  double best_exact = std::numeric_limits<double>::infinity();
  for (std::size_t c = 0; c < std::min<std::size_t>(2, refined.size()); ++c) {
    auto [value, r] = refined[c];
    descend_rotation(r, value, exact_cost, 1e-2, 1e-7, 4);
    const Eigen::Matrix3d fitted =
        rotation_of(levenberg_marquardt(residuals_from(r), Eigen::VectorXd::Zero(3), 50)) * r;
    if (const double v = exact_cost(fitted); v < value) {
      value = v;
      r = fitted;
    }
    if (value < best_exact) {
      best_exact = value;
      best = r;
    }
  }
  return best;
}

Eigen::Matrix2cd mobius_of_rotation(const Eigen::Matrix3d& r) {
  std::vector<Eigen::Vector3d> x{Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
                                 Eigen::Vector3d::UnitZ(), -Eigen::Vector3d::UnitZ()};
  std::vector<Eigen::Vector3d> y;
  y.reserve(x.size());
  for (const auto& p : x) y.emplace_back(r * p);
  return fit_sphere_mobius(x, y);
}

DomainAlignment align_spheres(const CanonicalDomain& a, const CanonicalDomain& b,
                              const DomainLocator& locator_b, const Samples& s,
                              const AlignmentOptions& options) {
  DomainAlignment result;
  result.kind = DomainKind::Sphere;
  std::vector<Eigen::Vector3d> x, y;
  for (const auto& [i, j] : options.landmarks) {
    x.emplace_back(a.points.row(i).transpose());
    y.emplace_back(b.points.row(j).transpose());
  }
  if (x.size() >= 3) {
    result.sphere = fit_sphere_mobius(x, y);
    result.method = "landmarks";
    return result;
  }
  const SphereField field(locator_b);
  Eigen::Matrix3d r = best_rotation(a, s, field, locator_b);
  result.method = "conformal factor";
  if (!x.empty()) {
    // A few landmarks: the rotation pulled onto them (it stays a rotation, so the centre of
    // mass stays at the origin).
    const auto residual = [&](const Eigen::VectorXd& p) {
      const Eigen::Matrix3d rp =
          Eigen::AngleAxisd(p.norm(),
                            p.norm() > 0 ? Eigen::Vector3d(p / p.norm()) : Eigen::Vector3d::UnitX())
              .toRotationMatrix() *
          r;
      Eigen::VectorXd res(3 * static_cast<Eigen::Index>(x.size()));
      for (std::size_t k = 0; k < x.size(); ++k)
        res.segment<3>(3 * static_cast<Eigen::Index>(k)) = rp * x[k] - y[k];
      return res;
    };
    const Eigen::VectorXd p = levenberg_marquardt(residual, Eigen::VectorXd::Zero(3));
    if (p.norm() > 0)
      r = Eigen::AngleAxisd(p.norm(), Eigen::Vector3d(p / p.norm())).toRotationMatrix() * r;
    result.method = "conformal factor + landmarks";
  }
  result.sphere = mobius_of_rotation(r);
  return result;
}

// --- The disk ---------------------------------------------------------------------------------

cd as_complex(const Eigen::Vector3d& p) {
  return {p.x(), p.y()};
}

// The disk isometry that puts the centre of mass of the area (faces' centroids weighted by their
// 3D area share) at the origin, by repeated moves of the current centre to the origin.
Mobius centring(const CanonicalDomain& d, const Triangles& triangles) {
  Mobius total;
  for (int it = 0; it < 200; ++it) {
    cd centre = 0;
    for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
      cd c = 0;
      for (int k = 0; k < 3; ++k)
        c += apply_mobius(total, as_complex(d.points.row(triangles(f, k))));
      centre += d.area_share(f) * c / 3.0;
    }
    if (std::abs(centre) < 1e-12) break;
    if (std::abs(centre) >= 0.999) centre *= 0.999 / std::abs(centre);
    total = normalized(compose(translation_to_origin(centre), total));
  }
  return total;
}

DomainAlignment align_disks(const CanonicalDomain& a, const CanonicalDomain& b,
                            const DomainLocator& locator_a, const DomainLocator& locator_b,
                            const Samples& s, const AlignmentOptions& options) {
  DomainAlignment result;
  result.kind = DomainKind::Disk;
  const Mobius ta = centring(a, locator_a.triangles());
  const Mobius tb = centring(b, locator_b.triangles());
  const Mobius tb_inverse = inverse(tb);
  // B's conformal factor on a grid over the centred disk.
  Grid grid;
  grid.nu = grid.nv = 129;
  grid.value.resize(grid.nu, grid.nv);
  const auto grid_point = [&](int i, int n) { return -1.0 + 2.0 * i / (n - 1); };
  for (int i = 0; i < grid.nu; ++i) {
    for (int j = 0; j < grid.nv; ++j) {
      cd z(grid_point(i, grid.nu), grid_point(j, grid.nv));
      if (std::abs(z) > 0.999) z *= 0.999 / std::abs(z);
      const cd w = apply_mobius(tb_inverse, z);
      grid.value(i, j) = read_factor(locator_b, {w.real(), w.imag(), 0});
    }
  }
  std::vector<cd> centred(s.vertex.size());
  for (std::size_t i = 0; i < s.vertex.size(); ++i)
    centred[i] = apply_mobius(ta, as_complex(a.points.row(s.vertex[i])));
  const auto cost = [&](double angle) {
    const cd turn = std::polar(1.0, angle);
    return weighted_mismatch(s, [&](int i) {
      const cd z = turn * centred[static_cast<std::size_t>(i)];
      return grid.at((z.real() + 1) / 2 * (grid.nu - 1), (z.imag() + 1) / 2 * (grid.nv - 1));
    });
  };
  double best_angle = 0, best_cost = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 720; ++k) {
    const double angle = kTwoPi * k / 720;
    const double c = cost(angle);
    if (c < best_cost) {
      best_cost = c;
      best_angle = angle;
    }
  }
  // Refined on B's factor read exactly (the table's interpolation would shift the optimum).
  const auto exact_cost = [&](double angle) {
    const cd turn = std::polar(1.0, angle);
    return weighted_mismatch(s, [&](int i) {
      const cd w = apply_mobius(tb_inverse, turn * centred[static_cast<std::size_t>(i)]);
      return read_factor(locator_b, {w.real(), w.imag(), 0});
    });
  };
  // From the table's best and from 0 (a disk matched to itself), the better one kept.
  const auto polish = [&](double angle, double& value) {
    value = exact_cost(angle);
    for (double step = kTwoPi / 1440; step > 1e-9; step /= 2) {
      for (double sign : {-1.0, 1.0}) {
        const double c = exact_cost(angle + sign * step);
        if (c < value) {
          value = c;
          angle += sign * step;
        }
      }
    }
    return angle;
  };
  double zero_cost = 0;
  const double from_zero = polish(0.0, zero_cost);
  best_angle = polish(best_angle, best_cost);
  if (zero_cost <= best_cost) best_angle = from_zero;
  result.method = "conformal factor";
  const auto assemble = [&](const Eigen::VectorXd& p) {
    // T_B^-1 . rotation . (move by c) . T_A, with c = p0 + i p1 and the angle p2.
    const cd c(p(0), p(1));
    const Mobius move = std::abs(c) < 0.999 ? translation_to_origin(-c) : Mobius{};
    return normalized(compose(tb_inverse, compose(rotation(p(2)), compose(move, ta))));
  };
  Eigen::VectorXd p(3);
  p << 0, 0, best_angle;
  if (!options.landmarks.empty()) {
    const auto residual = [&](const Eigen::VectorXd& q) {
      const Mobius m = assemble(q);
      Eigen::VectorXd res(2 * static_cast<Eigen::Index>(options.landmarks.size()));
      for (std::size_t k = 0; k < options.landmarks.size(); ++k) {
        const auto [i, j] = options.landmarks[k];
        const cd d = apply_mobius(m, as_complex(a.points.row(i))) - as_complex(b.points.row(j));
        res(2 * static_cast<Eigen::Index>(k)) = d.real();
        res(2 * static_cast<Eigen::Index>(k) + 1) = d.imag();
      }
      return res;
    };
    p = levenberg_marquardt(residual, p);
    result.method = "landmarks";
  }
  result.disk = assemble(p);
  return result;
}

// --- The torus --------------------------------------------------------------------------------

Eigen::Matrix2d basis_matrix(const std::array<cd, 2>& l) {
  Eigen::Matrix2d m;
  m << l[0].real(), l[1].real(), l[0].imag(), l[1].imag();
  return m;
}

double distortion_of(const Eigen::Matrix2d& l) {
  const Eigen::Vector2d sv = Eigen::JacobiSVD<Eigen::Matrix2d>(l).singularValues();
  return sv(0) / sv(1);
}

// The lattice vector of `torus` nearest p (p reduced modulo the lattice to the smallest
// representative of its class among the neighbours of the rounded coordinates).
Eigen::Vector2d reduce_modulo(const CanonicalDomain& torus, const Eigen::Vector2d& p) {
  const Eigen::Matrix2d basis = basis_matrix(torus.lattice);
  const Eigen::Vector2d s = basis.inverse() * p;
  Eigen::Vector2d best = p;
  for (int dm = -1; dm <= 1; ++dm) {
    for (int dn = -1; dn <= 1; ++dn) {
      const Eigen::Vector2d q =
          p - basis * Eigen::Vector2d(std::round(s.x()) + dm, std::round(s.y()) + dn);
      if (q.norm() < best.norm()) best = q;
    }
  }
  return best;
}

DomainAlignment align_tori(const CanonicalDomain& a, const CanonicalDomain& b,
                           const DomainLocator& locator_b, const Samples& s,
                           const AlignmentOptions& options) {
  const Eigen::Matrix2d basis_a = basis_matrix(a.lattice), basis_b = basis_matrix(b.lattice);
  // Candidate linear maps: B's reduced basis changed by every unimodular matrix with entries in
  // {-1, 0, 1}; the least distorted ones (several when a lattice has symmetries, always L and -L).
  std::vector<Eigen::Matrix2d> maps;
  double least = std::numeric_limits<double>::infinity();
  std::vector<std::pair<double, Eigen::Matrix2d>> all;
  for (int p = -1; p <= 1; ++p) {
    for (int q = -1; q <= 1; ++q) {
      for (int r = -1; r <= 1; ++r) {
        for (int t = -1; t <= 1; ++t) {
          if (p * t - q * r != 1) continue;
          Eigen::Matrix2d u;
          u << p, q, r, t;
          const Eigen::Matrix2d l = basis_b * u * basis_a.inverse();
          const double k = distortion_of(l);
          least = std::min(least, k);
          all.emplace_back(k, l);
        }
      }
    }
  }
  for (const auto& [k, l] : all) {
    if (k <= least * (1 + 1e-6) + 1e-9) maps.push_back(l);
  }
  // The bases' own correspondence (U = I) first: on a symmetric torus the candidates tie, and a
  // surface matched to itself should then get the identity, not its half-turn.
  const Eigen::Matrix2d direct = basis_b * basis_a.inverse();
  std::stable_sort(maps.begin(), maps.end(),
                   [&](const Eigen::Matrix2d& x, const Eigen::Matrix2d& y) {
                     return (x - direct).norm() < (y - direct).norm();
                   });
  // B's conformal factor over its fundamental parallelogram (periodic grid).
  Grid grid;
  grid.nu = grid.nv = 64;
  grid.periodic_u = grid.periodic_v = true;
  grid.value.resize(grid.nu, grid.nv);
  for (int i = 0; i < grid.nu; ++i) {
    for (int j = 0; j < grid.nv; ++j) {
      const Eigen::Vector2d p = basis_b * Eigen::Vector2d(double(i) / grid.nu, double(j) / grid.nv);
      grid.value(i, j) = read_factor(locator_b, {p.x(), p.y(), 0});
    }
  }
  const Eigen::Matrix2d to_b_coordinates = basis_b.inverse();
  const auto field_b = [&](const Eigen::Vector2d& p) {
    const Eigen::Vector2d c = to_b_coordinates * p;
    return grid.at(c.x() * grid.nu, c.y() * grid.nv);
  };
  DomainAlignment best;
  best.kind = DomainKind::Torus;
  // Per candidate: the landmarks' fit (sum of squared offsets, 0 without landmarks) and the
  // conformal factors' mismatch; the best fit wins, ties (one landmark fits any L) to the
  // better matched factors.
  double best_fit = std::numeric_limits<double>::infinity();
  double best_factor = std::numeric_limits<double>::infinity();
  for (const Eigen::Matrix2d& l : maps) {
    // At most 1000 samples for the searches (the table's and the exact one).
    const Samples few = subsample(s, 1000);
    std::vector<Eigen::Vector2d> few_mapped(few.vertex.size());
    for (std::size_t i = 0; i < few.vertex.size(); ++i) {
      few_mapped[i] = l * a.points.row(few.vertex[i]).head<2>().transpose();
    }
    const auto cost = [&](const Eigen::Vector2d& t) {
      return weighted_mismatch(
          few, [&](int i) { return field_b(few_mapped[static_cast<std::size_t>(i)] + t); });
    };
    Eigen::Vector2d shift = Eigen::Vector2d::Zero();
    double fit = 0;
    std::string method;
    if (!options.landmarks.empty()) {
      // The mean offset, each taken modulo the lattice next to the first one.
      std::vector<Eigen::Vector2d> offsets;
      for (const auto& [i, j] : options.landmarks) {
        offsets.emplace_back(b.points.row(j).head<2>().transpose() -
                             l * a.points.row(i).head<2>().transpose());
      }
      Eigen::Vector2d sum = Eigen::Vector2d::Zero();
      for (const auto& o : offsets) sum += offsets.front() + reduce_modulo(b, o - offsets.front());
      shift = sum / static_cast<double>(offsets.size());
      for (const auto& o : offsets) fit += reduce_modulo(b, o - shift).squaredNorm();
      method = "lattice + landmarks";
    } else {
      // 32 x 32 translations on the table, the best 4 refined there; those and t = 0, the two
      // best by the factor read exactly polished on it (the table's interpolation can misorder
      // translations where the factor is steep; a torus matched to itself then gets t = 0).
      const int n = 32;
      std::vector<std::pair<double, Eigen::Vector2d>> starts;
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          const Eigen::Vector2d t = basis_b * Eigen::Vector2d(double(i) / n, double(j) / n);
          starts.emplace_back(cost(t), t);
        }
      }
      std::sort(starts.begin(), starts.end(),
                [](const auto& x, const auto& y) { return x.first < y.first; });
      starts.resize(4);
      const auto exact_cost = [&](const Eigen::Vector2d& t) {
        return weighted_mismatch(few, [&](int i) {
          const Eigen::Vector2d p = few_mapped[static_cast<std::size_t>(i)] + t;
          return read_factor(locator_b, {p.x(), p.y(), 0});
        });
      };
      // Coordinate descent along the lattice's basis, at most 4 moves a step size.
      const auto descend = [&](const auto& f, Eigen::Vector2d& t0, double& value, double largest,
                               double smallest) {
        for (double step = largest; step > smallest; step /= 2) {
          for (int move = 0; move < 4; ++move) {
            bool moved = false;
            for (int axis = 0; axis < 2; ++axis) {
              for (double sign : {-1.0, 1.0}) {
                const Eigen::Vector2d t = t0 + sign * step * basis_b.col(axis);
                const double c = f(t);
                if (c < value) {
                  value = c;
                  t0 = t;
                  moved = true;
                }
              }
            }
            if (!moved) break;
          }
        }
      };
      for (auto& [value, t] : starts) {
        descend(cost, t, value, 0.5 / n, 1e-3);
        value = exact_cost(t);
      }
      // t = 0 as it is (not moved on the table first).
      starts.emplace_back(exact_cost(Eigen::Vector2d::Zero()), Eigen::Vector2d::Zero());
      std::sort(starts.begin(), starts.end(),
                [](const auto& x, const auto& y) { return x.first < y.first; });
      double score = std::numeric_limits<double>::infinity();
      // Then Levenberg-Marquardt on the residuals (as for the sphere's rotation).
      const auto residuals = [&](const Eigen::VectorXd& t) {
        return weighted_residuals(few, [&](int i) {
          const Eigen::Vector2d p = few_mapped[static_cast<std::size_t>(i)] + t;
          return read_factor(locator_b, {p.x(), p.y(), 0});
        });
      };
      for (std::size_t c = 0; c < 2; ++c) {
        auto [value, t] = starts[c];
        descend(exact_cost, t, value, 1e-2, 1e-7);
        // (Its start copied a coordinate at a time: GCC 12 with AVX reads the copy of a Vector2d
        // into a VectorXd as a 4-double packet and warns, falsely, of an access out of bounds.)
        const Eigen::Vector2d fitted =
            levenberg_marquardt(residuals, Eigen::VectorXd{{t.x(), t.y()}}, 50);
        if (const double v = exact_cost(fitted); v < value) {
          value = v;
          t = fitted;
        }
        if (value < score) {
          score = value;
          shift = t;
        }
      }
      method = "lattice + conformal factor";
    }
    const double factor = weighted_mismatch(s, [&](int i) {
      const Eigen::Vector2d p =
          l * a.points.row(s.vertex[static_cast<std::size_t>(i)]).head<2>().transpose() + shift;
      return read_factor(locator_b, {p.x(), p.y(), 0});
    });
    const bool better_fit = fit < best_fit - 1e-8;
    const bool tied_fit = std::abs(fit - best_fit) <= 1e-8;
    // Factors equal to the grid's interpolation (a symmetry of the surface) keep the earlier.
    const bool better_factor = factor < best_factor - 1e-6 * (1 + best_factor);
    if (better_fit || (tied_fit && better_factor)) {
      best_fit = fit;
      best_factor = factor;
      best.torus_linear = l;
      best.torus_shift = shift;
      best.method = method;
    }
  }
  best.torus_distortion = distortion_of(best.torus_linear);
  const cd ta = a.modulus, tb = b.modulus;
  best.modulus_distance = std::acosh(1 + std::norm(ta - tb) / (2 * ta.imag() * tb.imag()));
  return best;
}

}  // namespace

Eigen::Vector3d apply_sphere_mobius(const Eigen::Matrix2cd& m, const Eigen::Vector3d& x) {
  return from_homogeneous(m * to_homogeneous(x.normalized()));
}

Eigen::Matrix2cd fit_sphere_mobius(const std::vector<Eigen::Vector3d>& x,
                                   const std::vector<Eigen::Vector3d>& y) {
  if (x.size() < 3 || x.size() != y.size()) {
    throw InvalidInput("fit_sphere_mobius: needs three or more pairs of points");
  }
  // w1 (c z1 + d z2) - w2 (a z1 + b z2) = 0 for each pair, in the unknowns (a, b, c, d).
  Eigen::MatrixXcd rows(static_cast<Eigen::Index>(x.size()), 4);
  for (std::size_t k = 0; k < x.size(); ++k) {
    const Eigen::Vector2cd z = to_homogeneous(x[k].normalized()),
                           w = to_homogeneous(y[k].normalized());
    Eigen::RowVector4cd row(-w(1) * z(0), -w(1) * z(1), w(0) * z(0), w(0) * z(1));
    rows.row(static_cast<Eigen::Index>(k)) = row / row.norm();
  }
  const Eigen::JacobiSVD<Eigen::MatrixXcd> svd(rows, Eigen::ComputeFullV);
  const Eigen::Vector4cd v = svd.matrixV().col(3);
  Eigen::Matrix2cd m0;
  m0 << v(0), v(1), v(2), v(3);
  m0 = unit_determinant(m0);
  if (x.size() == 3) return m0;
  // Least squares on the chordal distances: m = m0 (I + D), D = [[p0 + i p1, p2 + i p3],
  // [p4 + i p5, -(p0 + i p1)]].
  const auto assemble = [&](const Eigen::VectorXd& p) {
    Eigen::Matrix2cd d;
    d << cd(p(0), p(1)), cd(p(2), p(3)), cd(p(4), p(5)), -cd(p(0), p(1));
    return unit_determinant(m0 * (Eigen::Matrix2cd::Identity() + d));
  };
  const auto residual = [&](const Eigen::VectorXd& p) {
    const Eigen::Matrix2cd m = assemble(p);
    Eigen::VectorXd r(3 * static_cast<Eigen::Index>(x.size()));
    for (std::size_t k = 0; k < x.size(); ++k) {
      r.segment<3>(3 * static_cast<Eigen::Index>(k)) =
          apply_sphere_mobius(m, x[k]) - y[k].normalized();
    }
    return r;
  };
  return assemble(levenberg_marquardt(residual, Eigen::VectorXd::Zero(6)));
}

Eigen::Vector3d apply_alignment(const DomainAlignment& alignment, const Eigen::Vector3d& point) {
  switch (alignment.kind) {
    case DomainKind::Sphere:
      return apply_sphere_mobius(alignment.sphere, point);
    case DomainKind::Disk: {
      const cd w = apply_mobius(alignment.disk, cd(point.x(), point.y()));
      return {w.real(), w.imag(), 0};
    }
    case DomainKind::Torus: {
      const Eigen::Vector2d w = alignment.torus_linear * point.head<2>() + alignment.torus_shift;
      return {w.x(), w.y(), 0};
    }
  }
  return point;
}

DomainAlignment inverse(const DomainAlignment& alignment) {
  DomainAlignment result = alignment;
  result.sphere = alignment.sphere.inverse();
  result.disk = inverse(alignment.disk);
  result.torus_linear = alignment.torus_linear.inverse();
  result.torus_shift = -result.torus_linear * alignment.torus_shift;
  if (alignment.kind == DomainKind::Torus) result.modulus_distance = alignment.modulus_distance;
  return result;
}

DomainAlignment align_domains(const CanonicalDomain& a, const CanonicalDomain& b,
                              const AlignmentOptions& options) {
  if (a.kind != b.kind) {
    throw InvalidInput(std::string("the surfaces map to different domains: ") + enum_name(a.kind) +
                       " and " + enum_name(b.kind) + " (matching needs the same topology)");
  }
  for (const auto& [i, j] : options.landmarks) {
    if (i < 0 || i >= a.points.rows() || j < 0 || j >= b.points.rows()) {
      throw InvalidInput("landmark " + std::to_string(i) + " " + std::to_string(j) +
                         ": a vertex out of range (A has " + std::to_string(a.points.rows()) +
                         " vertices, B " + std::to_string(b.points.rows()) + ")");
    }
  }
  const DomainLocator locator_a(a), locator_b(b);
  const Samples s = sample_vertices(a, locator_a.triangles(), options.max_samples);
  DomainAlignment result;
  switch (a.kind) {
    case DomainKind::Sphere:
      result = align_spheres(a, b, locator_b, s, options);
      break;
    case DomainKind::Disk:
      result = align_disks(a, b, locator_a, locator_b, s, options);
      break;
    case DomainKind::Torus:
      result = align_tori(a, b, locator_b, s, options);
      break;
  }
  // The mismatch of the conformal factors under the final map, read exactly (not from grids).
  result.factor_mismatch = std::sqrt(weighted_mismatch(s, [&](int i) {
    return read_factor(
        locator_b,
        apply_alignment(result, a.points.row(s.vertex[static_cast<std::size_t>(i)]).transpose()));
  }));
  return result;
}

}  // namespace ricci
