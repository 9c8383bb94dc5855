#pragma once
/// \file
/// Aligning two surfaces' canonical domains (issue 29, docs/matching.md): the conformal
/// automorphism (or, for tori of different moduli, the affine map) taking surface A's domain to
/// surface B's.
///
/// - Sphere: a Moebius transformation (PSL(2, C), acting on the unit sphere through
///   stereographic projection). With three or more landmarks, the one fitting them: the linear
///   fit of w (c z + d) = a z + b, then Levenberg-Marquardt on the chordal distances. With fewer,
///   both maps have their area's centre of mass at the origin (sphere_map), which leaves a
///   rotation: the one that best aligns the two conformal factors, searched over 4096 rotations
///   and refined; landmarks, if any, then pull it by least squares.
/// - Disk: an isometry of the Poincare disk (SU(1, 1)). Without landmarks both domains are moved
///   so that their area's centre of mass is at the origin, and the rotation that best aligns the
///   conformal factors is searched; landmarks (a boundary point and an interior point suffice)
///   fit all three parameters.
/// - Torus: x -> L x + t, L the real linear map taking A's lattice basis to B's (a similarity
///   when the moduli agree), among the bases of least distortion the one that fits best; t from
///   the landmarks (their mean offset modulo the lattice) or the best alignment of the conformal
///   factors over a grid of translations, refined.

#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "ricci/match/canonical_domain.hpp"
#include "ricci/numerics/mobius.hpp"

namespace ricci {

/// A map of canonical domains (one of the three, by `kind`).
struct DomainAlignment {
  DomainKind kind = DomainKind::Sphere;
  Eigen::Matrix2cd sphere = Eigen::Matrix2cd::Identity();  ///< z -> (a z + b) / (c z + d)
  Mobius disk;                                             ///< an isometry of the disk
  Eigen::Matrix2d torus_linear = Eigen::Matrix2d::Identity();
  Eigen::Vector2d torus_shift = Eigen::Vector2d::Zero();
  /// "landmarks", or "conformal factor" (centre of mass, then the rotation or translation that
  /// best aligns the conformal factors), or both ("conformal factor + landmarks").
  std::string method;
  /// Root mean square, over A's sampled vertices weighted by area, of the difference of the two
  /// conformal factors (log area factors) at corresponding points: 0 for conformally equivalent
  /// surfaces aligned exactly.
  double factor_mismatch = 0;
  /// Torus: sigma_max / sigma_min of L (1: the moduli agree), and the hyperbolic distance between
  /// the two moduli in the upper half plane.
  double torus_distortion = 1;
  double modulus_distance = 0;
};

/// The image of a domain point of A in B's domain (sphere: unit vectors; disk and torus: (x, y,
/// 0)).
Eigen::Vector3d apply_alignment(const DomainAlignment& alignment, const Eigen::Vector3d& point);
/// The inverse map (B's domain to A's).
DomainAlignment inverse(const DomainAlignment& alignment);

/// Options of align_domains.
struct AlignmentOptions {
  /// Pairs (vertex of A, vertex of B), mesh vertex indices.
  std::vector<std::pair<int, int>> landmarks;
  int max_samples = 4000;  ///< vertices of A sampled for the conformal factor's comparison
};

/// Aligns A's canonical domain with B's (see the file comment).
/// \throw InvalidInput when the two domains differ in kind, or a landmark is out of range
DomainAlignment align_domains(const CanonicalDomain& a, const CanonicalDomain& b,
                              const AlignmentOptions& options = {});

/// The Moebius transformation (PSL(2, C) on the sphere) fitted to pairs x_i -> y_i of unit
/// vectors: exact for three pairs, least squares on the chordal distances for more.
/// \pre at least three pairs, x distinct
Eigen::Matrix2cd fit_sphere_mobius(const std::vector<Eigen::Vector3d>& x,
                                   const std::vector<Eigen::Vector3d>& y);
/// The action of a PSL(2, C) matrix on the unit sphere (stereographic projection from (0,0,1)).
Eigen::Vector3d apply_sphere_mobius(const Eigen::Matrix2cd& m, const Eigen::Vector3d& x);

}  // namespace ricci
