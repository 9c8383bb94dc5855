#pragma once
/// \file
/// Shape matching through conformal maps (issue 29, docs/matching.md): two surfaces of the same
/// topology (closed genus 0, a disk, closed genus 1) are mapped to their canonical domain
/// (canonical_domain.hpp), aligned there (alignment.hpp), and every vertex of A is sent to the
/// point of B whose domain image its own image lands on: a face of B and barycentric weights.
/// The classic route of Gu, Wang, Chan, Thompson and Yau (2004, brains on the sphere) and Wang,
/// Gu and Samaras (2006, faces on the disk).

#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "ricci/match/alignment.hpp"
#include "ricci/match/canonical_domain.hpp"
#include "ricci/mesh/mesh.hpp"
#include "ricci/param/distortion.hpp"

namespace ricci {

/// A map from the vertices of one mesh onto the surface of another: per vertex, a face of the
/// target and the barycentric weights of its corners (non-negative, summing to 1).
struct SurfaceMap {
  Eigen::VectorXi face;                              ///< #V of the source: a face of the target
  Eigen::Matrix<double, Eigen::Dynamic, 3> weights;  ///< #V by 3
  /// Vertices whose domain image no target face held (outside a polygonal disk's boundary by
  /// rounding or by the polygon's chords): given the nearest face, weights clamped.
  int outside = 0;
  double max_outside = 0;  ///< the largest miss, in barycentric weight
};

/// The 3D points a map sends the source's vertices to (#V by 3).
Positions mapped_positions(const Mesh& target, const SurfaceMap& map);

/// Options of match_surfaces.
struct MatchOptions {
  CanonicalDomainOptions domain;
  /// Pairs (vertex of A, vertex of B), mesh vertex indices. Sphere: three or more fix the
  /// Moebius transformation; disk: a boundary pair and an interior pair fix the isometry.
  std::vector<std::pair<int, int>> landmarks;
  bool reverse = false;    ///< also map B onto A (with the inverse alignment)
  int max_samples = 4000;  ///< AlignmentOptions::max_samples
};

/// A landmark after matching: where vertex a of A landed on B, against vertex b of B.
struct LandmarkResidual {
  int a = -1, b = -1;
  double distance = 0;  ///< 3D distance on B's surface points, in B's units
};

/// What match_surfaces returns.
struct MatchResult {
  DomainKind domain = DomainKind::Sphere;
  bool converged = false;  ///< both canonical maps converged without inverted faces
  std::string message;     ///< why not, when not
  /// Both domains exactly Moebius-invariant (CanonicalDomain::exact): a Moebius copy then
  /// matches to rounding; otherwise to the meshes' resolution.
  bool exact = false;
  DomainAlignment alignment;
  SurfaceMap forward;   ///< A's vertices on B
  SurfaceMap backward;  ///< B's vertices on A (MatchOptions::reverse)
  std::vector<LandmarkResidual> landmarks;
  double landmark_rms = 0, landmark_max = 0;  ///< 3D distances, B's units
  double b_diagonal = 0;                      ///< B's bounding-box diagonal
  /// The piecewise-linear map from A's triangles to the triangles of their vertices' images on
  /// B (flattened each in its own plane): angle distortion sigma_max / sigma_min and the log area
  /// ratio (both surfaces at total area 1). A face whose image turns against B's surface (its
  /// normal against B's at its corners) counts as flipped.
  Distortion distortion;
  /// Invariants of each surface (its canonical domain): the torus modulus, 0 otherwise.
  std::complex<double> modulus_a{0, 0}, modulus_b{0, 0};
  int flow_iterations_a = 0, flow_iterations_b = 0;
  double domain_seconds = 0, align_seconds = 0, locate_seconds = 0, seconds = 0;
};

/// Matches A to B (see the file comment).
/// \throw InvalidInput when either mesh is not one of the three topologies, they differ, a
///        landmark is out of range, or a mesh has defects; TopologyError for non-manifold meshes
MatchResult match_surfaces(const Mesh& a, const Mesh& b, const MatchOptions& options = {});

/// Frames of a morph from A to target positions (#V of A by 3, e.g. mapped_positions): frame k
/// of n is (1 - t) A + t target with t = k / (n - 1), on A's faces. With `rigid`, the target is
/// first moved by the rotation and translation that best fit it onto A (least squares over the
/// vertices, weighted by A's vertex areas), so that the morph changes shape, not place.
/// \throw InvalidInput when frames < 2 or the target's rows differ from A's vertices
std::vector<Positions> morph_frames(const Mesh& a, const Positions& target, int frames,
                                    bool rigid = true);

}  // namespace ricci
