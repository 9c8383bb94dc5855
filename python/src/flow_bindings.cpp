/// \file
/// Bindings of the metric and flow modules: schemes, targets, the flow options and results, and
/// flow_mesh.

#include <string>

#include "bindings.hpp"
#include "ricci/errors.hpp"
#include "ricci/flow/mesh_flow.hpp"
#include "ricci/flow/ricci_flow.hpp"
#include "ricci/flow/target.hpp"
#include "ricci/mesh/validate.hpp"
#include "ricci/metric/scheme.hpp"

namespace ricci::python {
namespace {

/// "fit" or "unit" (the command line's --init names).
PackingInit parse_packing_init(const std::string& name) {
  return parse_enum<PackingInit>(name, "packing_init");
}

/// "natural", "flat", "uniform" or "values".
TargetKind parse_target_kind(const std::string& name) {
  return parse_enum<TargetKind>(name, "target kind");
}

/// Lets an enum be built from its ricci name: `Scheme("thurston")`.
template <class E>
void construct_from_name(py::enum_<E>& e, E (*parse)(const std::string&)) {
  e.def(py::init([parse](const std::string& name) { return parse(name); }), py::arg("name"));
  bind_enum_names(e);
}

}  // namespace

void bind_flow(py::module_& m) {
  py::enum_<Scheme> scheme(m, "Scheme", "The discrete conformal metrics ricci supports.");
  for (const SchemeTraits& row : kSchemeTraits) scheme.value(row.identifier, row.scheme);
  construct_from_name(scheme, &parse_scheme);
  m.def("scheme_name", &scheme_name, py::arg("scheme"));

  py::enum_<Geometry> geometry(m, "Geometry", "The background geometry of a discrete metric.");
  geometry.value("Euclidean", Geometry::Euclidean).value("Hyperbolic", Geometry::Hyperbolic);
  construct_from_name(geometry, &parse_geometry);

  py::enum_<PackingInit> packing(m, "PackingInit", "How the initial circle packing is chosen.");
  packing.value("Fit", PackingInit::Fit).value("UnitRadii", PackingInit::UnitRadii);
  construct_from_name(packing, &parse_packing_init);

  py::enum_<FlowSolver> solver(m, "FlowSolver", "Which solver runs the flow.");
  solver.value("Newton", FlowSolver::Newton).value("Gradient", FlowSolver::Gradient);
  construct_from_name(solver, &parse_flow_solver);

  py::enum_<EdgeFlips> flips(m, "EdgeFlips",
                             "Intrinsic Delaunay edge flips during the flow (vertex scaling).");
  flips.value("Auto", EdgeFlips::Auto)
      .value("Off", EdgeFlips::Off)
      .value("Delaunay", EdgeFlips::Delaunay);
  construct_from_name(flips, &parse_edge_flips);

  py::enum_<FlowStatus>(m, "FlowStatus", "Why a flow stopped.")
      .value("Converged", FlowStatus::Converged)
      .value("MaxIterations", FlowStatus::MaxIterations)
      .value("LineSearchFailed", FlowStatus::LineSearchFailed)
      .value("SolverFailed", FlowStatus::SolverFailed)
      .value("Cancelled", FlowStatus::Cancelled);
  m.def("flow_status_name", &flow_status_name, py::arg("status"));

  py::enum_<BoundaryMode> boundary(m, "BoundaryMode",
                                   "How boundary vertices are treated by the flat targets.");
  boundary.value("Free", BoundaryMode::Free)
      .value("DiskUniform", BoundaryMode::DiskUniform)
      .value("DiskLength", BoundaryMode::DiskLength)
      .value("Geodesic", BoundaryMode::Geodesic);
  construct_from_name(boundary, &parse_boundary_mode);

  py::enum_<TargetKind> kind(m, "TargetKind", "Kinds of target flow_mesh builds.");
  kind.value("Natural", TargetKind::Natural)
      .value("Flat", TargetKind::Flat)
      .value("Uniform", TargetKind::Uniform)
      .value("Values", TargetKind::Values);
  construct_from_name(kind, &parse_target_kind);

  StructBinding<StructureOptions>(m, "StructureOptions", "Options of the conformal structure.")
      .enum_field("scheme", &StructureOptions::scheme, &parse_scheme,
                  "Scheme (or its name: 'thurston', 'tangential', 'inversive-distance', "
                  "'vertex-scaling', 'virtual-radius')")
      .enum_field("geometry", &StructureOptions::geometry, &parse_geometry,
                  "Geometry (or 'euclidean', 'hyperbolic')")
      .field("hyperbolic_length_scale", &StructureOptions::hyperbolic_length_scale,
             "hyperbolic: factor on the input lengths (0: the input gets area 2 pi |chi|)")
      .enum_field("packing_init", &StructureOptions::packing_init, &parse_packing_init,
                  "PackingInit (or 'fit', 'unit'); Thurston and tangential only")
      .field("max_intersection_angle", &StructureOptions::max_intersection_angle,
             "largest intersection angle Phi the Thurston fit may use (radians)")
      .field("fit_sweeps", &StructureOptions::fit_sweeps,
             "most Gauss-Seidel sweeps of the radius fit")
      .field("fit_tolerance", &StructureOptions::fit_tolerance,
             "stop the fit when a sweep lowers the squared error by less than this fraction")
      .keyword_constructor()
      .repr();

  StructBinding<ConformalStructure>(m, "ConformalStructure",
                                    "Constants of the unified form and the fitted log radii.")
      .readonly("scheme", &ConformalStructure::scheme, "")
      .readonly("geometry", &ConformalStructure::geometry, "")
      .readonly("length_scale", &ConformalStructure::length_scale,
                "hyperbolic: factor applied to the input lengths")
      .readonly("epsilon", &ConformalStructure::epsilon, "#V scheme constants")
      .readonly("eta", &ConformalStructure::eta, "#E edge constants")
      .readonly("initial_u", &ConformalStructure::initial_u, "#V log radii of the initial metric")
      .repr();

  StructBinding<StructureResult>(m, "StructureResult", "What make_conformal_structure returns.")
      .readonly("structure", &StructureResult::structure, "")
      .readonly("fit_rms_relative_error", &StructureResult::fit_rms_relative_error,
                "sqrt(sum (l - lbar)^2 / sum lbar^2) of the initial metric")
      .readonly("fit_max_relative_error", &StructureResult::fit_max_relative_error,
                "max |l - lbar| / lbar")
      .readonly("fit_sweeps", &StructureResult::fit_sweeps, "sweeps the fit used")
      .repr();

  StructBinding<Cone>(m, "Cone", "A cone singularity: vertex and curvature (2 pi - cone angle).")
      .field("vertex", &Cone::vertex, "vertex index")
      .field("curvature", &Cone::curvature, "radians")
      .keyword_constructor()
      .repr()
      .cls()
      .def(py::init([](int vertex, double curvature) {
             return Cone{vertex, curvature};
           }),
           py::arg("vertex"), py::arg("curvature"));

  StructBinding<Target>(m, "Target", "Per-vertex prescription of a flow.")
      .readonly("curvature", &Target::curvature, "#V target curvature (ignored where fixed)")
      .flags("fixed", &Target::fixed, "#V bools: u stays at its initial value")
      .readonly("description", &Target::description, "one line for reports")
      .repr();

  StructBinding<TargetSpec>(m, "TargetSpec", "The target, in whole-mesh vertex indices.")
      .enum_field("kind", &TargetSpec::kind, &parse_target_kind,
                  "TargetKind (or 'flat', 'uniform', 'values')")
      .field("cones", &TargetSpec::cones, "Flat: list of Cone (assign a new list to change it)")
      .enum_field("boundary", &TargetSpec::boundary, &parse_boundary_mode,
                  "BoundaryMode (or 'free', 'disk', 'disk-length', 'geodesic')")
      .field("values", &TargetSpec::values, "Values: #V curvatures")
      .keyword_constructor()
      .repr();

  StructBinding<IterationRecord>(m, "IterationRecord", "One iteration of a flow.")
      .readonly("iteration", &IterationRecord::iteration, "0 is the initial state")
      .readonly("max_error", &IterationRecord::max_error,
                "max |K-bar - K| over vertices with a target after the step")
      .readonly("rms_error", &IterationRecord::rms_error, "root mean square of the same")
      .readonly("step_length", &IterationRecord::step_length, "alpha of u += alpha delta")
      .readonly("backtracks", &IterationRecord::backtracks, "step halvings of the line search")
      .readonly("triangle_failures", &IterationRecord::triangle_failures,
                "trial steps rejected for breaking a triangle inequality")
      .readonly("flips", &IterationRecord::flips, "edges flipped by the accepted step")
      .readonly("chord", &IterationRecord::chord,
                "a chord step: the previous factorisation, as it was")
      .readonly("seconds", &IterationRecord::seconds, "wall time since the solve started")
      .repr();

  StructBinding<FlowOptions>(m, "FlowOptions", "Options of the Ricci flow solvers.")
      .enum_field("solver", &FlowOptions::solver, &parse_flow_solver,
                  "FlowSolver (or 'newton', 'gradient')")
      .field("tolerance", &FlowOptions::tolerance,
             "stop when max |K-bar - K| <= tolerance (radians)")
      .enum_field("flips", &FlowOptions::flips, &parse_edge_flips,
                  "EdgeFlips (or 'auto': Delaunay flips for vertex scaling, 'off', 'delaunay')")
      .field("simplicial_flips", &FlowOptions::simplicial_flips,
             "only flips that keep a simplicial complex (no double edge, no loop)")
      .field("max_iterations", &FlowOptions::max_iterations,
             "0: 200 for Newton, 1000000 for the gradient flow")
      .field("gradient_step", &FlowOptions::gradient_step,
             "gradient flow time step; 0 picks 1 / (largest diagonal entry of the Hessian)")
      .field("armijo", &FlowOptions::armijo, "sufficient decrease in the line search")
      .field("max_backtracks", &FlowOptions::max_backtracks,
             "line search halvings before the flow gives up")
      .field("use_cholmod", &FlowOptions::use_cholmod,
             "CHOLMOD when available, Eigen's solver otherwise")
      .field("reuse_factorization_cg_iterations", &FlowOptions::reuse_factorization_cg_iterations,
             "refactorise when conjugate gradients preconditioned by the last factor need more "
             "than this many iterations; 0 refactorises every step")
      .field("chord_error", &FlowOptions::chord_error,
             "Newton: reuse the last factorisation as it is (chord steps) below this error")
      .field("start_u", &FlowOptions::start_u,
             "where the flow starts: empty, the structure's initial u; else #V log factors near "
             "the solution (fixed vertices keep their initial u; dropped when its rms error is "
             "not below the initial metric's)")
      .property(
          "progress", [](const FlowOptions& o) { return progress_callable(o.progress); },
          [](FlowOptions& o, const py::object& f) { o.progress = make_progress(f); },
          "callable(IterationRecord) called after every iteration (holding the GIL); returning "
          "False stops the flow (status Cancelled), None or True lets it go on")
      .keyword_constructor()
      .repr();

  StructBinding<FlowTimings>(m, "FlowTimings", "Wall time spent in each phase, seconds.")
      .readonly("setup", &FlowTimings::setup, "")
      .readonly("assembly", &FlowTimings::assembly, "")
      .readonly("analysis", &FlowTimings::analysis, "")
      .readonly("factorization", &FlowTimings::factorization, "")
      .readonly("solve", &FlowTimings::solve, "")
      .readonly("line_search", &FlowTimings::line_search, "")
      .readonly("total", &FlowTimings::total, "")
      .repr();

  StructBinding<FlowResult>(m, "FlowResult", "The flow on one component.")
      .readonly("converged", &FlowResult::converged, "")
      .readonly("status", &FlowResult::status, "FlowStatus")
      .computed(
          "message", [](const FlowResult& r) { return message_with_fixes(r.message, r.fixes); },
          "why it stopped, in words (with the keywords that may help, when it stopped short)")
      .computed(
          "fixes", [](const FlowResult& r) { return fix_pairs(r.fixes); },
          "(keyword, value) pairs that may let the flow converge, best first")
      .readonly("u", &FlowResult::u, "#V final log radii")
      .readonly("curvature", &FlowResult::curvature, "#V final curvature K")
      .readonly("target_curvature", &FlowResult::target_curvature, "#V K-bar")
      .readonly("lengths", &FlowResult::lengths, "#E final edge lengths")
      .computed(
          "triangles",
          [](const FlowResult& r) -> const Triangles& { return r.intrinsic.topology().triangles; },
          "#F by 3 final triangulation (the intrinsic Delaunay one after flips)")
      .computed(
          "flips", [](const FlowResult& r) { return r.intrinsic.flips(); },
          "edges flipped over the whole flow")
      .computed(
          "isometric_flips", [](const FlowResult& r) { return r.intrinsic.isometric_flips(); },
          "the first flips: the input metric retriangulated isometrically")
      .computed(
          "eta", [](const FlowResult& r) -> const Eigen::VectorXd& { return r.intrinsic.eta(); },
          "#E eta on the final triangulation (set by the flips)")
      .computed(
          "blocked_flips", [](const FlowResult& r) { return r.intrinsic.blocked_flips(); },
          "non-Delaunay edges left")
      .readonly("iterations", &FlowResult::iterations, "")
      .readonly("max_error", &FlowResult::max_error, "final max |K-bar - K|")
      .readonly("error_floor", &FlowResult::error_floor,
                "the smallest max error double arithmetic resolves at the final metric")
      .computed(
          "flipped_edges",
          [](const FlowResult& r) -> const std::vector<int>& {
            return r.intrinsic.flipped_edges();
          },
          "every accepted flip in order (edge indices of the input topology)")
      .readonly("history", &FlowResult::history, "IterationRecord list, initial state first")
      .readonly("timings", &FlowResult::timings, "FlowTimings")
      .readonly("analyses", &FlowResult::analyses, "")
      .readonly("factorizations", &FlowResult::factorizations, "")
      .readonly("cg_iterations", &FlowResult::cg_iterations, "")
      .readonly("chord_steps", &FlowResult::chord_steps,
                "Newton steps made with the previous factorisation as it was")
      .readonly("linear_solver", &FlowResult::linear_solver, "Cholesky backend (Newton)")
      .readonly("gauss_bonnet_relative_error", &FlowResult::gauss_bonnet_relative_error, "")
      .readonly("total_area", &FlowResult::total_area, "hyperbolic: area of the final metric")
      .repr();

  StructBinding<MeshFlowOptions>(m, "MeshFlowOptions", "Options of flow_mesh.")
      .field("structure", &MeshFlowOptions::structure, "StructureOptions")
      .field("target", &MeshFlowOptions::target, "TargetSpec")
      .field("flow", &MeshFlowOptions::flow, "FlowOptions")
      .field("vertex_labels", &MeshFlowOptions::vertex_labels,
             "numbers messages show for vertices; empty: the mesh's own indices")
      .keyword_constructor()
      .repr();

  StructBinding<ComponentFlow>(m, "ComponentFlow", "Result of one component.")
      .readonly("vertices", &ComponentFlow::vertices, "whole-mesh index of each component vertex")
      .readonly("euler_characteristic", &ComponentFlow::euler_characteristic, "")
      .readonly("genus", &ComponentFlow::genus, "")
      .readonly("boundary_loops", &ComponentFlow::boundary_loops, "")
      .readonly("flow", &ComponentFlow::flow,
                "FlowResult in component-local indices (the doubled surface's when doubled)")
      .readonly("doubled", &ComponentFlow::doubled,
                "flowed again glued to its mirror image (boundary triangles blocked the flow)")
      .readonly("first_attempt_message", &ComponentFlow::first_attempt_message,
                "why the flow on the component itself failed (doubled only)")
      .repr();

  StructBinding<MeshFlowResult>(m, "MeshFlowResult", "What flow_mesh returns.")
      .readonly("converged", &MeshFlowResult::converged, "every component converged")
      .readonly("status", &MeshFlowResult::status,
                "Converged, or the FlowStatus of the first component that did not converge")
      .computed(
          "message", [](const MeshFlowResult& r) { return message_with_fixes(r.message, r.fixes); },
          "why each component stopped, in words (with the keywords that may help)")
      .computed(
          "fixes", [](const MeshFlowResult& r) { return fix_pairs(r.fixes); },
          "(keyword, value) pairs that may let the flow converge, best first")
      .readonly("max_error", &MeshFlowResult::max_error, "over all components")
      .readonly("u", &MeshFlowResult::u, "#V final log radii")
      .readonly("curvature", &MeshFlowResult::curvature, "#V final curvature")
      .readonly("target_curvature", &MeshFlowResult::target_curvature,
                "#V target (final curvature where u was fixed)")
      .computed(
          "edges", [](const MeshFlowResult& r) { return r.intrinsic.topology().edge_vertices; },
          "#E by 2 edge end vertices (topology.edge_vertices), the order of `lengths`")
      .readonly("lengths", &MeshFlowResult::lengths, "#E final lengths")
      .computed(
          "triangles", [](const MeshFlowResult& r) { return r.intrinsic.topology().triangles; },
          "#F by 3 final triangulation: the input's, or its intrinsic Delaunay triangulation "
          "after flips (same vertices)")
      .computed(
          "flips", [](const MeshFlowResult& r) { return r.intrinsic.flips(); },
          "edges flipped, all components")
      .computed(
          "eta",
          [](const MeshFlowResult& r) -> const Eigen::VectorXd& { return r.intrinsic.eta(); },
          "#E eta of the structure on the final triangulation (set by the flips)")
      .computed(
          "blocked_flips", [](const MeshFlowResult& r) { return r.intrinsic.blocked_flips(); },
          "non-Delaunay edges left")
      .computed(
          "history",
          [](const MeshFlowResult& r) {
            std::vector<std::vector<IterationRecord>> out;
            for (const ComponentFlow& c : r.components) out.push_back(c.flow.history);
            return out;
          },
          "per component: its IterationRecord list")
      .computed(
          "timings",
          [](const MeshFlowResult& r) {
            std::vector<FlowTimings> out;
            for (const ComponentFlow& c : r.components) out.push_back(c.flow.timings);
            return out;
          },
          "per component: its FlowTimings")
      .computed(
          "fit_error", [](const MeshFlowResult& r) { return r.structure.fit_rms_relative_error; },
          "structure.fit_rms_relative_error: RMS relative length error of the initial packing")
      .readonly("structure", &MeshFlowResult::structure, "StructureResult")
      .readonly("target", &MeshFlowResult::target, "Target")
      .computed(
          "topology",
          [](const MeshFlowResult& r) -> const Topology& { return r.intrinsic.topology(); },
          "Topology")
      .readonly("components", &MeshFlowResult::components, "ComponentFlow list")
      .readonly("setup_seconds", &MeshFlowResult::setup_seconds, "")
      .readonly("total_seconds", &MeshFlowResult::total_seconds, "")
      .repr();

  m.def(
      "flow_mesh",
      [](const Mesh& mesh, MeshFlowOptions options) {
        validate_mesh(mesh, "flow_mesh");  // flow_mesh's precondition
        return run_without_gil<MeshFlowResult>(options.flow,
                                               [&] { return flow_mesh(mesh, options); });
      },
      py::arg("mesh"), py::arg("options") = MeshFlowOptions{},
      "Runs the Ricci flow on every component of a mesh (validated first). Raises "
      "TopologyError, InvalidInput (inadmissible target, naming the vertex), SolverError.");

  m.def("parse_curvature", &parse_curvature, py::arg("text"),
        "Parses a curvature value: '1.5', 'pi', '-pi/2', '3*pi/4'.");
  m.def("parse_cone_list", &parse_cone_list, py::arg("text"), "Parses cones 'V:K,V:K,...'.");
}

}  // namespace ricci::python
