// `ricci spline`: a manifold spline over the flat metric with cones.
#include <CLI/CLI.hpp>
#include <iostream>
#include <memory>

#include "command_support.hpp"
#include "commands.hpp"
#include "json_output.hpp"
#include "ricci/mesh/io.hpp"
#include "ricci/spline/manifold_spline.hpp"
#ifdef RICCI_HAVE_RENDER
#include "render_command.hpp"
#endif

namespace ricci::cli {
namespace {

struct SplineArgs {
  std::string mesh;
  InputArgs input;          ///< --repair[=MODE], --strict, --largest-component (input_options.hpp)
  std::string output;       ///< the spline surface (.obj)
  std::string control_net;  ///< --control-net: the control net (.obj), optional
  int refine = SplineOptions{}.refine;
  double smoothness = SplineOptions{}.smoothness;
  /// --cones as for param; empty: by topology (none with boundary or genus 1, auto otherwise)
  std::string cones;
  std::string scheme = scheme_name(SplineOptions{}.param.structure.scheme);
  std::string flips = edge_flips_name(SplineOptions{}.param.flow.flips);
  double tolerance = SplineOptions{}.param.flow.tolerance;
  std::string report;
  bool json = false;
  bool progress = false;
  std::string pictures;  ///< --pictures: folder for the pictures (render_command.hpp)
};

int run_spline(const SplineArgs& args) {
  SplineOptions options;
  options.refine = args.refine;
  options.smoothness = args.smoothness;
  options.param.flow.tolerance = args.tolerance;
  options.param.structure.scheme = parse_scheme(args.scheme);
  options.param.flow.flips = parse_edge_flips(args.flips);
  check_output_is_not_input(args.output, {args.mesh, args.cones});
  if (!args.control_net.empty()) {
    check_output_is_not_input(args.control_net, {args.mesh, args.cones, args.output});
  }
  if (!args.report.empty()) check_output_is_not_input(args.report, {args.mesh, args.cones});
  const ReadResult read = read_input(args.mesh, args.input);
  print_warnings(read);
  if (!args.cones.empty()) {
    options.choose_cone_mode = false;
    apply_cones_option(args.cones, args.mesh, read, options.param);
  }
  const SplineResult result =
      run_with_progress(args.mesh, args.progress, args.json, "spline", options.param.flow,
                        [&] { return fit_manifold_spline(read.mesh, options); });
  nlohmann::json report = spline_report(result, options);
  if (!args.control_net.empty()) report["control_net_file"] = args.control_net;
  if (!finish_report(args.mesh, args.output, args.report, read, args.input, report,
                     result.converged, result.message)) {
    return kNotConverged;
  }
  write_obj(args.output, result.surface);
  if (!args.control_net.empty()) write_obj(args.control_net, result.control_net);
#ifdef RICCI_HAVE_RENDER
  write_manifold_spline_pictures(args.pictures, result);
#endif
  if (args.json) {
    std::cout << report.dump(2) << "\n";
  } else {
    const SplineError& e = result.error;
    if (!result.parameterization_note.empty()) {
      std::cout << "  note: " << result.parameterization_note << "\n";
    }
    std::cout << args.mesh << " -> " << args.output << "\n"
              << "  cones " << result.param.cones.size() << ", surface "
              << result.surface.num_faces() << " faces (refine " << options.refine
              << "), control net " << result.control_net.num_vertices() << " points\n"
              << "  error / bbox diagonal: distance max " << e.max_distance << " rms "
              << e.rms_distance << ", parametric max " << e.max_parametric << " rms "
              << e.rms_parametric << "\n"
              << "  C1 jumps (relative): value " << result.continuity.relative_value_jump
              << ", gradient " << result.continuity.relative_gradient_jump << ", " << result.seconds
              << " s\n";
    if (!args.control_net.empty()) std::cout << "  wrote " << args.control_net << "\n";
    if (!args.report.empty()) std::cout << "  wrote " << args.report << "\n";
  }
  return kOk;
}

}  // namespace

Subcommand add_spline_command(CLI::App& app) {
  auto args = std::make_shared<SplineArgs>();
  CLI::App* cmd = app.add_subcommand(
      "spline",
      "Manifold spline: a C1 quadratic Powell-Sabin spline over the flat metric with cones, "
      "fitted to the mesh's positions; writes the spline surface as a triangle mesh "
      "(docs/splines.md).");
  cmd->add_option("MESH", args->mesh, "mesh file (.obj .off .ply .stl)")->required();
  cmd->add_option("-o,--output", args->output, "output .obj: the spline surface")->required();
  cmd->add_option("--control-net", args->control_net,
                  "also write the control net (Bezier ordinates) as an .obj");
  cmd->add_option("--refine", args->refine, "each quadratic piece split K x K")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  cmd->add_option("--smooth", args->smoothness,
                  "dimensionless weight of the smoothness term (Hessian jumps)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--cones", args->cones,
                  "as for param; default: none with boundary or genus 1, auto otherwise");
  cmd->add_option("--scheme", args->scheme, "discrete metric (see ricci flow --help)")
      ->capture_default_str();
  cmd->add_option("--flips", args->flips, "intrinsic Delaunay edge flips of the flow")
      ->capture_default_str();
  cmd->add_option("--tol", args->tolerance, "flow tolerance on max |K-bar - K|")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--report", args->report,
                  "write a JSON report: errors, C1 jumps, fit, timings, parameterization");
  cmd->add_flag("--json", args->json, "print the report as JSON");
  cmd->add_flag("--progress", args->progress, "print flow iterations on stderr");
  add_input_options(cmd, args->input);
#ifdef RICCI_HAVE_RENDER
  cmd->add_option("--pictures", args->pictures,
                  "write domain.png, control_net.png and surface.png (the three stages "
                  "from one camera) and layout.png (the flat layout with its cones) into "
                  "this folder (created when missing)");
#endif

  return {cmd, [args] { return run_spline(*args); }};
}

}  // namespace ricci::cli
