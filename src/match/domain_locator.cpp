#include "ricci/match/domain_locator.hpp"

#include <cmath>

#include <Eigen/LU>

namespace ricci {

Eigen::Vector2d lattice_coordinates(const CanonicalDomain& torus, const Eigen::Vector2d& p) {
  Eigen::Matrix2d basis;
  basis << torus.lattice[0].real(), torus.lattice[1].real(), torus.lattice[0].imag(),
      torus.lattice[1].imag();
  return basis.inverse() * p;
}

DomainLocator::DomainLocator(const CanonicalDomain& domain) : domain_(domain) {
  triangles_ = domain.domain_triangles;
  if (!domain.domain_vertex.empty()) {
    for (Eigen::Index f = 0; f < triangles_.rows(); ++f) {
      for (int k = 0; k < 3; ++k) triangles_(f, k) = domain.domain_vertex[triangles_(f, k)];
    }
  }
  if (domain.kind == DomainKind::Sphere) {
    sphere_ = std::make_unique<SphereLocator>(domain.points, domain.domain_triangles);
  } else {
    plane_ = std::make_unique<PlanarLocator>(domain.domain_uv, domain.domain_triangles);
  }
}

FaceLocation DomainLocator::locate(const Eigen::Vector3d& point) const {
  if (sphere_) return sphere_->locate(point);
  const Eigen::Vector2d p = point.head<2>();
  if (domain_.kind == DomainKind::Disk) return plane_->locate(p);
  // Torus: the translate nearest the layout's centre first, then its neighbours.
  const Eigen::Vector2d centre = (plane_->lower() + plane_->upper()) / 2;
  const Eigen::Vector2d shift = lattice_coordinates(domain_, centre - p);
  const Eigen::Vector2d l0(domain_.lattice[0].real(), domain_.lattice[0].imag());
  const Eigen::Vector2d l1(domain_.lattice[1].real(), domain_.lattice[1].imag());
  const double m0 = std::round(shift.x()), n0 = std::round(shift.y());
  FaceLocation best;
  double best_miss = INFINITY;
  for (int ring = 0; ring <= 3; ++ring) {
    for (int dm = -ring; dm <= ring; ++dm) {
      for (int dn = -ring; dn <= ring; ++dn) {
        if (std::max(std::abs(dm), std::abs(dn)) != ring) continue;
        const Eigen::Vector2d q = p + (m0 + dm) * l0 + (n0 + dn) * l1;
        const Eigen::Vector2d lo = plane_->lower(), hi = plane_->upper();
        const double slack = 1e-9 * (hi - lo).maxCoeff();
        if ((q.array() < lo.array() - slack).any() || (q.array() > hi.array() + slack).any())
          continue;
        FaceLocation at = plane_->locate(q);
        if (at.face < 0) continue;
        if (at.inside) return at;
        if (at.outside_by < best_miss) {
          best_miss = at.outside_by;
          best = at;
        }
      }
    }
  }
  return best;
}

}  // namespace ricci
