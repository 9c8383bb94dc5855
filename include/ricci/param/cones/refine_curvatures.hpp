#pragma once
/// \file
/// Cone curvatures refined on the flow itself. The automatic selection chooses curvatures on
/// the flow linearised at the input metric, which misjudges strong cones: with few cones on a
/// closed surface of chi < 0 (eight with 4 cones: each near -pi) the flat metric's area
/// distortion falls by a further 5 to 30 % once the curvatures are moved along the gradient of
/// the flat metric's own distortion. Each step runs the flow to the flat metric (started where
/// the last step's Hessian predicts), so this is for a handful of cones on meshes where a flow
/// takes a fraction of a second: parameterize calls it where the linearised selection cannot
/// meet its bounds.

#include <vector>

#include <Eigen/Core>

#include "ricci/flow/flow_problem.hpp"
#include "ricci/flow/ricci_flow.hpp"
#include "ricci/flow/target.hpp"

namespace ricci {

/// Options of refine_cone_curvatures.
struct CurvatureRefinementOptions {
  int max_steps = 20;           ///< quasi-Newton steps at most
  double first_step = 0.5;      ///< largest curvature change of the first step (radians)
  double largest_step = 1.0;    ///< largest curvature change of any step (radians)
  double smallest_step = 1e-3;  ///< stop once a step this small (radians) finds no decrease
  /// Stop once a step lowers log(1 + E) by less than this, relative to 1 + log(1 + E).
  double relative_gain = 1e-4;
  /// Largest cone curvature (radians): the cone angle stays at least 2 pi - this.
  double max_curvature = 4.71238898038469;  // 1.5 pi, as ConeSelectionOptions
  /// Per cone (in the order given; empty: none), the lowest curvature a step may give it. A
  /// cone that starts below its bound may not go lower than it starts.
  std::vector<double> lower_bounds;
};

/// What refine_cone_curvatures returns.
struct CurvatureRefinement {
  std::vector<Cone> cones;        ///< the cones, curvatures refined (the same vertices and order)
  Eigen::VectorXd u;              ///< the flow's log factors at them (a start for a later flow)
  bool converged = false;         ///< the flow converged at `cones` (false: no flow did)
  double area_energy_before = 0;  ///< E of the flat metric with the cones as given
  double area_energy = 0;         ///< E with the refined curvatures
  int steps = 0;                  ///< accepted gradient steps
  int flows = 0;                  ///< flows run
};

/// Moves the cones' curvatures down the gradient of the flat metric's area distortion E (the
/// tutorial's eq. 9, each face's area scaled by e^{2 u_f}, u_f the mean over its corners), keeping
/// their sum on a closed surface (2 pi chi; with a free boundary the boundary takes the rest).
/// The gradient is exact: dE/dk = (H^-1 dE/du) at the cones, H the flow's Hessian at the flat
/// metric; the steps are quasi-Newton (BFGS), halved until the flow converges and E falls.
/// \pre cones on interior vertices; the problem's boundary (if any) free (u held at 0)
/// \throw InvalidInput as ricci_flow for an inadmissible start
CurvatureRefinement refine_cone_curvatures(const FlowProblem& problem,
                                           const std::vector<Cone>& cones, const FlowOptions& flow,
                                           const CurvatureRefinementOptions& options = {});

}  // namespace ricci
