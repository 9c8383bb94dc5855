#pragma once
/// \file
/// A surface's canonical domain for matching (issue 29, docs/matching.md): the conformal map of
/// a closed genus-0 mesh onto the unit sphere (sphere_map, its area's centre of mass at the
/// origin), of a disk onto the unit disk (the flat metric whose boundary turns in proportion to
/// its length, laid out and scaled so that the boundary's least-squares circle is the unit
/// circle), or of a closed genus-1 mesh onto its flat torus (the flat metric without cones, laid
/// out on the mesh cut along a homology basis, with the reduced basis of its period lattice
/// scaled to area 1). Two surfaces mapped to the same kind of domain are matched by aligning
/// there (alignment.hpp), and the domain's conformal factor is what an alignment without
/// landmarks compares.

#include <array>
#include <complex>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ricci/enum_names.hpp"
#include "ricci/flow/mesh_flow.hpp"
#include "ricci/mesh/mesh.hpp"

namespace ricci {

/// The canonical domains: the unit sphere (genus 0 closed), the unit disk (one boundary loop,
/// genus 0), a flat torus R^2 / lattice (genus 1 closed).
enum class DomainKind { Sphere, Disk, Torus };

template <>
struct EnumNames<DomainKind> {
  static constexpr const char* noun = "domain";
  static constexpr std::array<EnumName<DomainKind>, 3> names{{
      {DomainKind::Sphere, "sphere"},
      {DomainKind::Disk, "disk"},
      {DomainKind::Torus, "torus"},
  }};
};

/// layout_flow_options with FlowOptions::isometric_start off.
inline FlowOptions matching_flow_options() {
  FlowOptions options = layout_flow_options();
  options.isometric_start = false;
  return options;
}

/// Options of canonical_domain.
struct CanonicalDomainOptions {
  StructureOptions structure;  ///< the discrete metric (vertex scaling by default)
  /// Newton to 1e-12, Ptolemy flips from the input's triangulation (FlowOptions::isometric_start
  /// off): a mesh and its image under a Moebius transformation of space then get domains that
  /// differ by a conformal automorphism exactly, not to the mesh's resolution.
  FlowOptions flow = matching_flow_options();
};

/// A mesh in its canonical domain.
struct CanonicalDomain {
  DomainKind kind = DomainKind::Sphere;
  bool converged = false;  ///< the flow converged and the map has no inverted face
  std::string message;     ///< why not, when not
  /// The map is exactly Moebius-invariant (sphere and torus: Ptolemy-only flips and, on the
  /// sphere, the exact pole star). False where those failed (a triangle broken at the flow's
  /// start, a layout that folds) and the default flow and pole boundary were used instead, and
  /// always for the disk, whose boundary turns in proportion to its length.
  bool exact = false;
  /// #V by 3: each vertex's point: on the unit sphere; in the unit disk (z = 0); in the torus's
  /// plane (z = 0; one of its copies: the others differ by lattice vectors).
  Positions points;
  /// The domain's triangulation for point location. Sphere and disk: the mesh's triangles over
  /// `points`. Torus: the mesh cut open along its homology basis (a fundamental domain of the
  /// lattice), its vertices at `domain_uv`, each the copy of `domain_vertex[i]`.
  Triangles domain_triangles;
  Eigen::Matrix<double, Eigen::Dynamic, 2> domain_uv;  ///< disk and torus: #domain vertices by 2
  std::vector<int> domain_vertex;                      ///< per domain vertex: its mesh vertex
  /// Torus: the reduced basis of the lattice (|l0| <= |l1|, |Re(conj(l0) l1)| <= |l0|^2 / 2,
  /// l1 / l0 in the upper half plane), scaled so that the torus has area 1.
  std::array<std::complex<double>, 2> lattice{};
  /// Torus: the modulus tau = l1 / l0, in the fundamental domain of the modular group (|tau| >=
  /// 1, |Re tau| <= 1/2, Im tau > 0): the torus's conformal invariant.
  std::complex<double> modulus{0, 0};
  /// Per vertex: ln(domain area / 3D area) of its faces (both as shares of their totals, area
  /// weighted over the vertex's faces): the conformal factor 2u the domain gives the surface.
  Eigen::VectorXd log_area_factor;
  /// Per face: its 3D area as a share of the total (weights of the centre of mass).
  Eigen::VectorXd area_share;
  /// Disk and torus, second try: vertices the untangling moved off the conformal map so that no
  /// face folds (0 for a map that is the discrete conformal map itself).
  int untangled_vertices = 0;
  int flow_iterations = 0;
  double seconds = 0;
};

/// Maps one connected manifold mesh onto its canonical domain (see the file comment).
/// A map that fails with the exact options (see `exact`) is tried once more the default way.
/// \throw InvalidInput when the mesh is not one component, is not closed genus 0, a disk (one
///        boundary loop, genus 0) or closed genus 1 (the message names the topology), or has
///        defects (validate_mesh); TopologyError for non-manifold meshes
CanonicalDomain canonical_domain(const Mesh& mesh, const CanonicalDomainOptions& options = {});

/// The reduced basis of the lattice spanned by b0 and b1 (Lagrange-Gauss reduction), oriented so
/// that l1 / l0 has positive imaginary part. \pre b0, b1 linearly independent
std::array<std::complex<double>, 2> reduce_lattice(std::complex<double> b0,
                                                   std::complex<double> b1);

}  // namespace ricci
