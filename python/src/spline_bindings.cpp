/// \file
/// Bindings of the manifold splines (ricci/spline/manifold_spline.hpp).

#include <string>

#include "bindings.hpp"
#include "ricci/mesh/validate.hpp"
#include "ricci/spline/manifold_spline.hpp"

namespace ricci::python {
namespace {

/// (V, F) of a mesh as numpy arrays (float64 #V by 3, int32 #F by 3).
py::tuple mesh_arrays(const Mesh& mesh) {
  return py::make_tuple(mesh.positions, mesh.triangles);
}

}  // namespace

void bind_spline(py::module_& m) {
  StructBinding<SplineOptions>(m, "SplineOptions", "Options of fit_manifold_spline.")
      .field("param", &SplineOptions::param, "ParamOptions: cones, boundary, metric, flow")
      .field("choose_cone_mode", &SplineOptions::choose_cone_mode,
             "no cones for surfaces with boundary and for genus 1, param.cone_mode otherwise; "
             "False: param.cone_mode as given")
      .field("smoothness", &SplineOptions::smoothness,
             "dimensionless weight of the smoothness term (> 0)")
      .field("refine", &SplineOptions::refine,
             "each quadratic piece split refine x refine in the surface (>= 1)")
      .field("measure_distance", &SplineOptions::measure_distance,
             "measure the distance from the surface to the input (the parametric error always)")
      .field("continuity_samples", &SplineOptions::continuity_samples,
             "sample points per interior edge for the C1 check")
      .keyword_constructor()
      .repr();

  StructBinding<SplineError>(m, "SplineError",
                             "Fitting error at the surface's points, relative to the input's "
                             "bounding-box diagonal.")
      .readonly("bbox_diagonal", &SplineError::bbox_diagonal, "of the parameterized mesh")
      .readonly("max_parametric", &SplineError::max_parametric,
                "max |s(x) - PL(x)|: spline against the input's piecewise-linear map")
      .readonly("rms_parametric", &SplineError::rms_parametric, "")
      .readonly("max_distance", &SplineError::max_distance,
                "max distance from s(x) to the input surface; -1 when not measured")
      .readonly("rms_distance", &SplineError::rms_distance, "")
      .readonly("samples", &SplineError::samples, "surface points measured")
      .repr();

  StructBinding<ContinuityReport>(m, "ContinuityReport",
                                  "Value and gradient jumps across every interior edge.")
      .readonly("edges_checked", &ContinuityReport::edges_checked, "")
      .readonly("samples", &ContinuityReport::samples, "points, each evaluated from both faces")
      .readonly("max_value_jump", &ContinuityReport::max_value_jump, "")
      .readonly("max_gradient_jump", &ContinuityReport::max_gradient_jump,
                "neighbour's gradient rotated by the chart transition")
      .readonly("value_scale", &ContinuityReport::value_scale, "")
      .readonly("gradient_scale", &ContinuityReport::gradient_scale, "")
      .readonly("relative_value_jump", &ContinuityReport::relative_value_jump, "")
      .readonly("relative_gradient_jump", &ContinuityReport::relative_gradient_jump, "")
      .readonly("worst_edge", &ContinuityReport::worst_edge, "")
      .repr();

  StructBinding<SplineFit>(m, "SplineFit", "The least-squares fit of the spline.")
      .computed(
          "values", [](const SplineFit& f) { return f.data.values; },
          "#V by 3 fitted values at the vertices")
      .computed(
          "gradients", [](const SplineFit& f) { return f.data.gradients; },
          "#V by 6: columns 2c, 2c + 1 = gradient of coordinate c in the vertex's frame")
      .readonly("ordinates", &SplineFit::ordinates, "19 #F by 3 Bezier ordinates")
      .readonly("weight", &SplineFit::weight, "smoothness * h^3 used")
      .readonly("data_energy", &SplineFit::data_energy, "")
      .readonly("smoothness_energy", &SplineFit::smoothness_energy, "")
      .readonly("solve_residual", &SplineFit::solve_residual, "")
      .readonly("num_unknowns", &SplineFit::num_unknowns, "")
      .readonly("regularized", &SplineFit::regularized, "the system was singular")
      .computed(
          "solver", [](const SplineFit& f) { return std::string(f.solver); }, "")
      .readonly("seconds", &SplineFit::seconds, "")
      .repr();

  StructBinding<SplineResult>(m, "SplineResult", "What fit_manifold_spline returns.")
      .readonly("converged", &SplineResult::converged,
                "the parameterization converged (nothing else is filled otherwise)")
      .readonly("message", &SplineResult::message, "why not")
      .computed(
          "surface", [](const SplineResult& r) { return mesh_arrays(r.surface); },
          "(V, F): the spline evaluated, refine^2 triangles per piece, 6 pieces per face")
      .computed(
          "control_net", [](const SplineResult& r) { return mesh_arrays(r.control_net); },
          "(V, F): the Bezier ordinates, 4 triangles per piece")
      .computed(
          "surface_faces", [](const SplineResult& r) { return r.surface_samples.face; },
          "per surface point: the face of the domain holding it")
      .computed(
          "surface_barycentric",
          [](const SplineResult& r) { return r.surface_samples.barycentric; },
          "per surface point: its barycentric coordinates in that face")
      .computed(
          "values", [](const SplineResult& r) { return r.fit.data.values; },
          "#V by 3 fitted positions at the domain's vertices (fit.values)")
      .computed(
          "gradients", [](const SplineResult& r) { return r.fit.data.gradients; },
          "#V by 6 vertex-frame gradients (fit.gradients)")
      .computed(
          "cones", [](const SplineResult& r) { return r.param.cones; },
          "the parameterization's cones (param.cones; gradients held at 0 there)")
      .readonly("error", &SplineResult::error, "SplineError")
      .readonly("continuity", &SplineResult::continuity, "ContinuityReport")
      .readonly("fit", &SplineResult::fit, "SplineFit")
      .readonly("param", &SplineResult::param, "MeshParamResult: the domain (param.vertices, ...)")
      .readonly("seconds_param", &SplineResult::seconds_param, "")
      .readonly("seconds_fit", &SplineResult::seconds_fit, "")
      .readonly("seconds_evaluate", &SplineResult::seconds_evaluate, "")
      .readonly("seconds_error", &SplineResult::seconds_error, "")
      .readonly("seconds", &SplineResult::seconds, "")
      .repr();

  m.def(
      "fit_manifold_spline",
      [](const Mesh& mesh, SplineOptions options) {
        validate_mesh(mesh, "fit_manifold_spline");
        return run_without_gil<SplineResult>(options.param.flow,
                                             [&] { return fit_manifold_spline(mesh, options); });
      },
      py::arg("mesh"), py::arg("options") = SplineOptions{},
      "Manifold spline of a single-component manifold mesh (validated first): parameterization, "
      "C1 Powell-Sabin fit, surface, control net, error and continuity. Raises InvalidInput, "
      "TopologyError, SolverError.");
}

}  // namespace ricci::python
