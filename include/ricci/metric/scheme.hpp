#pragma once
/// \file
/// Discrete conformal structures in the unified form of THEORY.md section 2: every vertex carries
/// a radius gamma_i = exp(u_i) and a scheme constant epsilon_i, every edge a constant eta_ij, and
///     l_ij^2 = epsilon_i gamma_i^2 + epsilon_j gamma_j^2 + 2 eta_ij gamma_i gamma_j.
/// Changing u with epsilon and eta fixed is a discrete conformal deformation.

#include <array>
#include <cstddef>
#include <numbers>
#include <string>

#include <Eigen/Core>

#include "ricci/enum_names.hpp"
#include "ricci/mesh/mesh.hpp"
#include "ricci/mesh/topology.hpp"
#include "ricci/metric/geometry.hpp"

namespace ricci {

/// The discrete metrics ricci supports.
enum class Scheme {
  Tangential,         ///< epsilon = 1, eta = 1: circles touch (Phi = 0)
  Thurston,           ///< epsilon = 1, eta = cos Phi, Phi in [0, pi/2]: the tutorial's packing
  InversiveDistance,  ///< epsilon = 1, eta = inversive distance of the input circles
  VertexScaling,      ///< epsilon = 0, eta = lbar^2 / 2: discrete Yamabe flow
  VirtualRadius,      ///< epsilon = -1, eta = (lbar^2 + g_i^2 + g_j^2) / (2 g_i g_j)
};

/// What the rest of ricci needs to know about a scheme, besides how make_conformal_structure
/// builds it. A new scheme is a value of Scheme, a row of kSchemeTraits, and its cases in
/// make_conformal_structure (scheme.cpp, hyperbolic.cpp); everything else reads the row.
struct SchemeTraits {
  Scheme scheme;
  const char* name;        ///< printed and parsed (command line, JSON reports, Python strings)
  const char* alias;       ///< another name parse_scheme accepts, or nullptr
  const char* identifier;  ///< the value's name in Python's ricci.Scheme enum
  double epsilon;          ///< the scheme constant of every vertex (THEORY.md section 2)
  /// eta = cos Phi of two circles meeting at angle Phi (Thurston, tangential): the radii are fitted
  /// to the input lengths, and a face gives its vertex at most pi - Phi of angle (the
  /// single-vertex bound of check_admissible).
  bool circle_packing;
  /// Phi is fitted per edge in [0, max_intersection_angle] (Thurston) rather than fixed at 0
  /// (tangential, whose bound is then the widest a packing has).
  bool fitted_intersection_angles;
  /// The largest angle every face can give a vertex whatever the fitted constants: pi / 2 for
  /// packings (Phi up to pi / 2), pi otherwise. Sets the valence a cone needs without flips.
  double guaranteed_face_angle;
  /// Ptolemy flips keep the conformal class (epsilon = 0): EdgeFlips::Auto flips, Delaunay is
  /// allowed, and the exact common refinement exists.
  bool ptolemy_flips;
  /// The hyperbolic background is offered (its Ricci energy is convex there).
  bool hyperbolic;
};

/// One row per scheme, in the order of the enum (and of parse errors).
inline constexpr std::array<SchemeTraits, 5> kSchemeTraits{{
    {Scheme::Tangential, "tangential", nullptr, "Tangential", 1.0, true, false,
     std::numbers::pi / 2, false, true},
    {Scheme::Thurston, "thurston", nullptr, "Thurston", 1.0, true, true, std::numbers::pi / 2,
     false, true},
    {Scheme::InversiveDistance, "inversive-distance", nullptr, "InversiveDistance", 1.0, false,
     false, std::numbers::pi, false, true},
    {Scheme::VertexScaling, "vertex-scaling", "yamabe", "VertexScaling", 0.0, false, false,
     std::numbers::pi, true, true},
    {Scheme::VirtualRadius, "virtual-radius", nullptr, "VirtualRadius", -1.0, false, false,
     std::numbers::pi, false, false},
}};

/// The row of a scheme. \throw InvalidInput for a value outside the enum (a cast integer)
const SchemeTraits& scheme_traits(Scheme scheme);

/// The largest angle a face of the structure can give its vertex at a corner whose opposite edge
/// has constant eta: pi - arccos(eta) for circle packings, pi otherwise.
double max_face_angle(const SchemeTraits& traits, double eta);

/// Scheme names from kSchemeTraits: each row's name, then its alias.
template <>
struct EnumNames<Scheme> {
  static constexpr const char* noun = "scheme";
  static constexpr auto names = [] {
    constexpr std::size_t count = [] {
      std::size_t n = 0;
      for (const SchemeTraits& row : kSchemeTraits) n += row.alias ? 2 : 1;
      return n;
    }();
    std::array<EnumName<Scheme>, count> out{};
    std::size_t i = 0;
    for (const SchemeTraits& row : kSchemeTraits) {
      out[i++] = {row.scheme, row.name, NameRole::Primary};
      if (row.alias) out[i++] = {row.scheme, row.alias, NameRole::Alias};
    }
    return out;
  }();
};

/// "tangential", "thurston", "inversive-distance", "vertex-scaling", "virtual-radius".
const char* scheme_name(Scheme scheme);
/// Inverse of scheme_name (also accepts "yamabe" for vertex scaling).
/// \throw InvalidInput naming the string and listing the valid names
Scheme parse_scheme(const std::string& name);

/// One conformal class of metrics on a mesh: the constants of the unified form and the log radii
/// that best reproduce the input mesh's edge lengths.
///
/// In the hyperbolic background (THEORY.md section 9) the same constants enter
///     sinh^2(l_ij / 2) = (eps_i t_i^2 + eps_j t_j^2 + 2 eta_ij t_i t_j)
///                        / ((1 - eps_i t_i^2)(1 - eps_j t_j^2)),   t = e^u,
/// which for circle packings (eps = 1, t = tanh(r / 2)) is cosh l = cosh r_i cosh r_j +
/// eta sinh r_i sinh r_j, and for vertex scaling (eps = 0) is sinh(l / 2) = e^{(u_i + u_j) / 2}
/// sinh(lbar / 2) (hyperbolic discrete conformal equivalence).
struct ConformalStructure {
  Scheme scheme = Scheme::VertexScaling;
  Geometry geometry = Geometry::Euclidean;
  /// Hyperbolic background: the input lengths were multiplied by this before they were read as
  /// hyperbolic lengths (1 in the Euclidean background, where scale does not matter).
  double length_scale = 1.0;
  Eigen::VectorXd epsilon;    ///< #V scheme constants
  Eigen::VectorXd eta;        ///< #E edge constants
  Eigen::VectorXd initial_u;  ///< #V log radii of the initial (fitted) metric
};

/// How the initial circle packing is chosen.
enum class PackingInit {
  Fit,        ///< least-squares fit of the input lengths (tutorial eq. 1)
  UnitRadii,  ///< the tutorial's shortcut: gamma = 1, Phi = 0 (no conformality to the input)
};

/// "fit" or "unit" (the command line's --init, Python's packing_init).
template <>
struct EnumNames<PackingInit> {
  static constexpr const char* noun = "value";
  static constexpr std::array<EnumName<PackingInit>, 2> names{{
      {PackingInit::Fit, "fit"},
      {PackingInit::UnitRadii, "unit"},
  }};
};

/// Options of make_conformal_structure.
struct StructureOptions {
  /// Which discrete metric. Vertex scaling (discrete conformal equivalence) with intrinsic
  /// Delaunay flips reaches every admissible target and is the conformal one; Thurston's
  /// circle packing (the tutorial's) fits the input lengths only approximately and needs the
  /// single-vertex bound (valence-3 vertices of CAD meshes break it).
  Scheme scheme = Scheme::VertexScaling;
  PackingInit packing_init = PackingInit::Fit;  ///< Thurston and tangential only
  /// Largest intersection angle Phi the Thurston fit may use (radians; theory allows pi/2). Each
  /// face gives its vertex at most pi - Phi of angle, so at pi/2 a valence-4 vertex whose edges
  /// all fit best at pi/2 could never be flat (fertility.off has one); 80 degrees leaves room.
  double max_intersection_angle = 80.0 * 3.14159265358979323846 / 180.0;
  /// Background geometry. Hyperbolic: the input lengths, scaled by hyperbolic_length_scale, are
  /// the hyperbolic lengths the structure reproduces (Thurston: fits).
  Geometry geometry = Geometry::Euclidean;
  /// Hyperbolic background: factor on the input lengths; 0 picks the one that gives the input
  /// mesh (as Euclidean triangles) the total area 2 pi |chi| (4 pi when chi = 0), the area of
  /// the hyperbolic metric with zero vertex curvature, so that the flow changes sizes little.
  double hyperbolic_length_scale = 0.0;
  int fit_sweeps = 30;  ///< most Gauss-Seidel sweeps of the radius fit (Thurston, tangential)
  /// Stop the fit when a sweep lowers the sum of squared length errors by less than this
  /// fraction (the RMS error then changes in its fifth digit).
  double fit_tolerance = 1e-4;
};

/// What make_conformal_structure returns.
struct StructureResult {
  ConformalStructure structure;
  /// sqrt(sum (l - lbar)^2 / sum lbar^2) of the initial metric against the input lengths: 0 for
  /// the schemes that reproduce them exactly; the price of Thurston's and tangential's robustness.
  double fit_rms_relative_error = 0;
  double fit_max_relative_error = 0;  ///< max |l - lbar| / lbar
  int fit_sweeps = 0;                 ///< sweeps the fit used
};

/// Edge lengths of the mesh in R^3, #E in the order of topology.edge_vertices.
Eigen::VectorXd input_edge_lengths(const Mesh& mesh, const Topology& topology);

/// Builds the conformal structure of a scheme from the input edge lengths (in the geometry
/// options.geometry asks for).
/// \param input_lengths #E positive edge lengths (input_edge_lengths)
/// \throw InvalidInput when a length is not positive and finite
StructureResult make_conformal_structure(const Topology& topology,
                                         const Eigen::VectorXd& input_lengths,
                                         const StructureOptions& options = {});

}  // namespace ricci
