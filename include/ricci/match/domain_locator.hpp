#pragma once
/// \file
/// Point location in a mesh's canonical domain (canonical_domain.hpp): a domain point gives the
/// mesh face whose image holds it and the barycentric weights of its corners, so that any
/// per-vertex quantity (3D positions, the conformal factor) can be read at it. On a flat torus a
/// point is first moved by lattice vectors into the laid-out fundamental domain.

#include <memory>

#include <Eigen/Core>

#include "ricci/match/canonical_domain.hpp"
#include "ricci/match/point_location.hpp"

namespace ricci {

class DomainLocator {
 public:
  /// \param domain kept by reference: it must outlive the locator
  explicit DomainLocator(const CanonicalDomain& domain);
  /// The mesh face (the input's face index; weights over its corners in the input's order)
  /// holding a domain point: on the sphere any non-zero vector (its direction), in the disk and
  /// the torus (x, y, ignored z).
  FaceLocation locate(const Eigen::Vector3d& point) const;
  /// A per-vertex field (#V rows) read at a location, linearly.
  template <class Derived>
  Eigen::Matrix<double, 1, Derived::ColsAtCompileTime> interpolate(
      const Eigen::MatrixBase<Derived>& field, const FaceLocation& at) const {
    const auto& t = triangles();
    return at.weights(0) * field.row(t(at.face, 0)) + at.weights(1) * field.row(t(at.face, 1)) +
           at.weights(2) * field.row(t(at.face, 2));
  }
  /// The mesh's triangles (the faces `locate` names).
  const Triangles& triangles() const { return triangles_; }
  const CanonicalDomain& domain() const { return domain_; }

 private:
  const CanonicalDomain& domain_;
  Triangles triangles_;  ///< mesh faces: domain triangles mapped back to mesh vertices
  std::unique_ptr<SphereLocator> sphere_;
  std::unique_ptr<PlanarLocator> plane_;
};

/// The lattice coordinates (s0, s1) of a point p = s0 l0 + s1 l1 of the torus's plane.
Eigen::Vector2d lattice_coordinates(const CanonicalDomain& torus, const Eigen::Vector2d& p);

}  // namespace ricci
