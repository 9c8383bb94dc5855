#pragma once
/// \file
/// Singularity selection (tutorial section 5.2): where to put cones, and how much curvature each
/// carries, so that the flat metric distorts area little. Greedy placement on the linearised
/// problem (the Hessian L at the input metric: K(u) ~ K + L u): with the cone set S held at
/// u = 0, solve L u = -K on the other vertices; the vertex of largest |u| (the worst area
/// distortion) joins S. Vertices within 3 rings of a cone are left out of that choice and of the
/// measure: next to a cone u follows the cone's own log singularity. The nonlinear flow then holds
/// u at the cones and flattens the rest, so the cones take exactly the curvature the surface needs
/// there.

#include <vector>

#include "ricci/flow/mesh_flow.hpp"

namespace ricci {

/// Options of select_cones.
struct ConeSelectionOptions {
  int count = 0;  ///< place exactly this many cones; 0: as many as max_log_scale needs
  /// Add cones until max |u - mean u| (the largest log area scale factor of the linearised flat
  /// metric, relative to its mean) is at most this.
  double max_log_scale = 1.0;
  int max_cones = 64;  ///< never more than this many
  /// On a closed surface the first cone is needed before anything can be solved; try this many
  /// well-spread candidates for it (farthest-point samples) and keep the least distorting one.
  /// 1: take the vertex of most extreme curvature.
  int try_first_cone_candidates = 1;
  /// Boundary treatment while cones are chosen: Free holds the boundary at u = 0 (it flattens
  /// with no cone needed); the disk modes leave it free as well during selection.
  BoundaryMode boundary = BoundaryMode::Free;
  StructureOptions structure;  ///< the scheme whose Hessian linearises the flow
};

/// What select_cones returns.
struct ConeSelection {
  std::vector<int> vertices;          ///< cone vertices in the order they were chosen
  std::vector<double> max_log_scale;  ///< after each addition (linearised)
  /// Curvature each cone takes in the linearised solution (sums with the boundary to 2 pi chi).
  std::vector<double> linear_curvature;
};

/// Chooses cone vertices greedily (see the file comment).
/// \pre the mesh is a single connected component that passed validate_mesh
/// \throw InvalidInput when options are out of range
ConeSelection select_cones(const Mesh& mesh, const ConeSelectionOptions& options = {});

/// Rounds cone curvatures to multiples of pi/2 keeping their sum (which must itself be a
/// multiple of pi/2, as 2 pi chi minus a boundary total is for the flat targets): the cones with
/// the largest rounding remainders are rounded the other way until the sum matches. Cones whose
/// curvature rounds to 0 are dropped.
std::vector<Cone> quantize_cones(const std::vector<Cone>& cones, double total);

}  // namespace ricci
