#pragma once
/// \file
/// Target curvatures (THEORY.md section 6): what the flow should reach at every vertex, or that a
/// vertex keeps its log radius (a Dirichlet condition), and the checks that make a target
/// admissible: Gauss-Bonnet and the single-vertex bound.

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ricci/metric/scheme.hpp"

namespace ricci {

/// Per-vertex prescription of a flow.
struct Target {
  Eigen::VectorXd curvature;  ///< #V target curvature K-bar (ignored where fixed)
  std::vector<char> fixed;    ///< #V: 1 where u stays at its initial value (free boundary)
  std::string description;    ///< one line for reports, e.g. "flat with 4 cones"

  bool has_fixed_vertices() const;
};

/// A cone singularity: a vertex and the curvature it should carry (2 pi minus its cone angle).
struct Cone {
  int vertex = -1;
  double curvature = 0;
};

/// How boundary vertices are treated by the flat targets.
enum class BoundaryMode {
  Free,         ///< u fixed on the boundary: the curvature settles along it by itself
  DiskUniform,  ///< boundary curvature (2 pi chi - sum of cones) / m at each of m vertices
  DiskLength,   ///< the same total, shared in proportion to the boundary length at each vertex
  Geodesic,     ///< K-bar = 0 on the boundary: geodesic boundary (the hyperbolic default)
};

template <>
struct EnumNames<BoundaryMode> {
  static constexpr const char* noun = "boundary";
  static constexpr std::array<EnumName<BoundaryMode>, 4> names{{
      {BoundaryMode::Free, "free"},
      {BoundaryMode::DiskUniform, "disk"},
      {BoundaryMode::DiskLength, "disk-length"},
      {BoundaryMode::Geodesic, "geodesic"},
  }};
};

/// "free", "disk", "disk-length", "geodesic". \throw InvalidInput on any other string
BoundaryMode parse_boundary_mode(const std::string& name);
const char* boundary_mode_name(BoundaryMode mode);

/// Flat metric with cones: K-bar = 0 except at the cones; boundary vertices as `boundary` says.
/// \param input_lengths #E lengths used by DiskLength (input_edge_lengths)
/// \param vertex_labels numbers shown for vertices in messages (e.g. file indices); empty: the
///        vertex index
/// \throw InvalidInput when a cone names a vertex out of range, twice, or on the boundary
Target flat_target(const Topology& topology, const std::vector<Cone>& cones,
                   BoundaryMode boundary = BoundaryMode::Free,
                   const Eigen::VectorXd& input_lengths = {},
                   const std::vector<int>& vertex_labels = {});

/// K-bar_i = 2 pi chi / n on every vertex of each component (surface fairing).
Target uniform_target(const Topology& topology);

/// One value per vertex. \throw InvalidInput when the count differs from #V or a value is not
/// finite
Target values_target(const Topology& topology, const Eigen::VectorXd& values);

/// Options of check_admissible.
struct AdmissibilityOptions {
  /// |sum K-bar - 2 pi chi| allowed, relative to max(2 pi, sum |K-bar|).
  double gauss_bonnet_tolerance = 1e-9;
  /// Numbers shown for vertices in messages (e.g. their index in the input file); empty: the
  /// vertex index.
  std::vector<int> vertex_labels;
  /// The flow flips edges (EdgeFlips): a vertex's valence is not fixed, so the single-vertex
  /// lower bound does not apply (Gauss-Bonnet and K-bar < 2 pi, pi on the boundary, still do).
  bool edge_flips = false;
};

/// Rejects a target that cannot be reached: on every component without fixed vertices the target
/// must satisfy Gauss-Bonnet (hyperbolic background: sum K-bar > 2 pi chi, the area being
/// positive); every vertex with a target must satisfy the single-vertex bound
/// K-bar_i > 2 pi - sum over its faces of (pi - Phi_opposite) (pi instead of 2 pi on the boundary;
/// Phi = arccos eta for Thurston and tangential packings, 0 for the other schemes) and
/// K-bar_i < 2 pi (pi on the boundary); the lower bound is skipped with options.edge_flips.
/// \throw InvalidInput naming the vertex (or component), the value and the bound
void check_admissible(const Topology& topology, const ConformalStructure& structure,
                      const Target& target, const AdmissibilityOptions& options = {});

/// Parses a curvature value: a number, optionally with pi: "1.5", "pi", "-pi/2", "0.5pi",
/// "3*pi/4". \throw InvalidInput naming the text
double parse_curvature(const std::string& text);

/// Parses cones "V:K,V:K,..." (K as in parse_curvature). \throw InvalidInput naming the item
std::vector<Cone> parse_cone_list(const std::string& text);

/// Reads cones from a file, one "vertex curvature" pair per line ('#' starts a comment).
/// \throw IoError / InvalidInput naming the file and line
std::vector<Cone> read_cone_file(const std::string& path);

/// Reads one curvature value per line ('#' starts a comment).
/// \throw IoError / InvalidInput naming the file and line
Eigen::VectorXd read_values_file(const std::string& path);

}  // namespace ricci
