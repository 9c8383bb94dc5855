#pragma once
/// \file
/// Manifold splines (tutorial figs. 14, 16, 18; docs/splines.md): a surface parameterized over
/// its flat metric with cones, then fitted by a C1 quadratic Powell-Sabin spline over the affine
/// atlas, evaluated as a triangle mesh, with its control net and its fitting error.

#include <string>

#include "ricci/param/parameterize.hpp"
#include "ricci/spline/powell_sabin.hpp"
#include "ricci/spline/spline_fit.hpp"
#include "ricci/spline/spline_mesh.hpp"

namespace ricci {

/// Options of fit_manifold_spline.
struct SplineOptions {
  ParamOptions param;  ///< the parameterization (cones, boundary, flow)
  /// Pick the cone mode from the topology: none for surfaces with boundary (free boundary) and
  /// for closed genus 1, param.cone_mode otherwise (automatic cones by default). false: use
  /// param.cone_mode as given.
  bool choose_cone_mode = true;
  double smoothness = 1e-4;  ///< SplineFitOptions::smoothness (dimensionless)
  int refine = 2;            ///< each quadratic piece split refine x refine in the output surface
  /// Measure the distance from the spline surface to the input surface (point to triangle over
  /// the 2-ring of each sample's face); the parametric error is always measured.
  bool measure_distance = true;
  int continuity_samples = 5;  ///< sample points per interior edge for the C1 check
};

/// Fitting error at the output surface's vertices, relative to the input's bounding-box diagonal.
struct SplineError {
  double bbox_diagonal = 0;  ///< of the parameterized mesh's positions
  /// |s(x) - PL(x)|: the spline against the input's piecewise-linear map at the same parameter
  /// point x (both in the face holding x).
  double max_parametric = 0, rms_parametric = 0;
  /// Distance from s(x) to the input surface (nearest point over the faces of the 2-ring of x's
  /// face); -1 when not measured.
  double max_distance = -1, rms_distance = -1;
  int samples = 0;
};

/// What fit_manifold_spline returns.
struct SplineResult {
  bool converged = false;  ///< the parameterization converged (nothing else is filled otherwise)
  std::string message;     ///< why not
  MeshParamResult param;   ///< the flat metric, cut, layout and atlas the spline lives on
  /// Set when the spline does not live on the parameterization asked for, and why: the
  /// vertex-scaling map drew some input faces flipped (needles between exact images), where no
  /// spline piece can live, and the domain is Thurston's circle-packing map instead.
  std::string parameterization_note;
  SplineDomain domain;
  SplineFit fit;  ///< values: fitted positions (#V by 3); gradients in the vertex frames
  Mesh surface;   ///< the spline evaluated (SplineOptions::refine)
  SplineTessellation surface_samples;  ///< the same points with their faces and barycentrics
  Mesh control_net;                    ///< Bezier ordinates as a triangle mesh
  SplineError error;
  ContinuityReport continuity;
  double seconds_param = 0, seconds_fit = 0, seconds_evaluate = 0, seconds_error = 0;
  double seconds = 0;
};

/// The domain of a converged parameterization: its mesh's topology, the cut mesh's layout as
/// charts, gradients held at 0 at the cones.
/// \throw InvalidInput as spline_domain
SplineDomain spline_domain(const Parameterization& param);

/// Error of a spline surface against a mesh (the parameterized one: same vertices and faces as
/// the domain).
/// \param positions #V by 3 positions of the mesh the domain's triangles index
SplineError measure_spline_error(const SplineDomain& domain, const Positions& positions,
                                 const SplineTessellation& samples, bool measure_distance = true);

/// Parameterizes the mesh, fits the spline to its positions, evaluates surface and control net,
/// measures error and continuity.
/// \throw as parameterize, spline_domain and fit_spline; InvalidInput when refine < 1
SplineResult fit_manifold_spline(const Mesh& mesh, const SplineOptions& options = {});

}  // namespace ricci
