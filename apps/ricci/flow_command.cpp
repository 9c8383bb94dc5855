// `ricci flow`: the discrete conformal metric that realises a target curvature.
#include <CLI/CLI.hpp>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>

#include "command_support.hpp"
#include "commands.hpp"
#include "fixes.hpp"
#include "json_output.hpp"
#include "progress.hpp"
#include "ricci/flow/mesh_flow.hpp"
#include "ricci/flow/ricci_flow.hpp"
#include "ricci/mesh/io.hpp"
#include "ricci/metric/scheme.hpp"

namespace ricci::cli {
namespace {

struct FlowArgs {
  std::string mesh;
  InputArgs input;  ///< --repair[=MODE], --strict, --largest-component (input_options.hpp)
  std::string scheme = scheme_name(StructureOptions{}.scheme);
  std::string geometry = "euclidean";
  std::string init = "fit";
  std::string target = "natural";
  std::string boundary;  ///< empty: free (euclidean) or geodesic (hyperbolic)
  std::string cones;
  std::string solver = "newton";
  std::string flips = edge_flips_name(FlowOptions{}.flips);
  double tolerance = FlowOptions{}.tolerance;
  int max_iterations = FlowOptions{}.max_iterations;
  double step = 0;
  std::string output;
  bool json = false;
  bool progress = false;
};

int run_flow(const FlowArgs& args) {
  MeshFlowOptions options;
  options.structure.scheme = parse_scheme(args.scheme);
  options.structure.geometry = parse_geometry(args.geometry);
  const bool hyperbolic = options.structure.geometry == Geometry::Hyperbolic;
  options.structure.packing_init = parse_enum<PackingInit>(args.init, "--init");
  options.flow.solver = parse_flow_solver(args.solver);
  options.flow.flips = parse_edge_flips(args.flips);
  options.flow.tolerance = args.tolerance;
  options.flow.max_iterations = args.max_iterations;
  options.flow.gradient_step = args.step;
  if (!args.output.empty()) {
    check_output_is_not_input(args.output, {args.mesh, args.cones, args.target});
  }

  const ReadResult read = read_input(args.mesh, args.input);
  print_warnings(read);
  const Mesh& mesh = read.mesh;

  TargetSpec& spec = options.target;
  spec.boundary = !args.boundary.empty() ? parse_boundary_mode(args.boundary)
                  : hyperbolic           ? BoundaryMode::Geodesic
                                         : BoundaryMode::Free;
  if (args.target == "natural") {
    spec.kind = TargetKind::Natural;
  } else if (args.target == "flat") {
    spec.kind = TargetKind::Flat;
  } else if (args.target == "free" || args.target == "disk" || args.target == "disk-length" ||
             args.target == "geodesic") {
    spec.kind = TargetKind::Flat;
    spec.boundary = parse_boundary_mode(args.target);
  } else if (args.target == "uniform") {
    spec.kind = TargetKind::Uniform;
  } else if (std::filesystem::is_regular_file(args.target)) {
    // Values are listed per vertex of the file; drop the rows of unreferenced vertices.
    const Eigen::VectorXd file_values = read_values_file(args.target);
    const auto file_vertices = static_cast<Eigen::Index>(read.file_vertices);
    const bool per_file_vertex = file_values.size() == file_vertices;
    if (!per_file_vertex && file_values.size() != mesh.num_vertices()) {
      throw InvalidInput(args.target + ": " + std::to_string(file_values.size()) +
                         " curvature values for the " + std::to_string(file_vertices) +
                         " vertices of " + args.mesh);
    }
    spec.kind = TargetKind::Values;
    spec.values.resize(mesh.num_vertices());
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      spec.values[v] = file_values[per_file_vertex ? read.vertex_map[v] : v];
    }
  } else {
    throw InvalidInput("--target: '" + args.target +
                       "' is neither natural, flat, free, disk, disk-length, geodesic, uniform "
                       "nor a file of per-vertex curvatures");
  }
  // Cone vertices are numbered as in the file (0-based).
  const std::vector<int> to_mesh = inverse_map(read.vertex_map);
  for (Cone cone : read_cones(args.cones)) {
    if (cone.vertex >= static_cast<int>(to_mesh.size()) || to_mesh[cone.vertex] < 0) {
      throw InvalidInput("--cones: vertex " + std::to_string(cone.vertex) + " is not a vertex of " +
                         args.mesh + " used by any face");
    }
    cone.vertex = to_mesh[cone.vertex];
    spec.cones.push_back(cone);
  }
  if (!spec.cones.empty() && spec.kind != TargetKind::Flat && spec.kind != TargetKind::Natural) {
    throw InvalidInput(
        "--cones needs a flat target (--target flat, free, disk, disk-length or geodesic)");
  }

  options.vertex_labels = read.vertex_map;  // messages number vertices as the file does
  const MeshFlowResult result = [&] {
    try {
      return run_with_progress(args.mesh, args.progress, args.json, "flow", options.flow,
                               [&] { return flow_mesh(mesh, options); });
    } catch (const InvalidInput& e) {
      // Gauss-Bonnet's refusal names the natural and uniform targets, but with --cones the
      // natural target is flat with those cones and the uniform one takes none: dropping the
      // cones is the fix where the target is the natural one, and no single option otherwise.
      const bool names_target =
          std::any_of(e.fixes().begin(), e.fixes().end(),
                      [](const OptionFix& f) { return f.option == "target"; });
      if (spec.cones.empty() || !names_target) throw;
      throw InvalidInput(e.what(), args.target == "natural" ? fixes_of({{"cones", ""}})
                                                            : std::vector<OptionFix>{});
    }
  }();

  nlohmann::json summary = flow_summary(result, options);
  summary["input"] = args.mesh;
  summary["warnings"] = read.warnings;
  if (read.repaired) summary["repair"] = repair_json(read, args.input);
  if (!args.output.empty()) {
    nlohmann::json full = summary;
    full["vertex_data"] = flow_arrays(result, read.vertex_map);
    write_file_atomically(args.output, [&](std::ostream& out) { out << full.dump(1) << "\n"; });
  }
  if (args.json) {
    std::cout << summary.dump(2) << "\n";
  } else {
    std::cout << args.mesh << ": " << (result.converged ? "converged" : "NOT converged")
              << ", max |K-bar - K| = " << std::scientific << std::setprecision(3)
              << result.max_error << std::defaultfloat << " ("
              << scheme_name(options.structure.scheme) << ", " << (hyperbolic ? "hyperbolic, " : "")
              << flow_solver_name(options.flow.solver) << ", " << result.target.description
              << ")\n";
    if (scheme_traits(options.structure.scheme).circle_packing) {
      std::cout << "  initial packing fits the input lengths with RMS relative error "
                << std::setprecision(3) << result.structure.fit_rms_relative_error << " (max "
                << result.structure.fit_max_relative_error << ")" << std::defaultfloat << "\n";
    }
    if (hyperbolic) {
      std::cout << "  input lengths scaled by " << std::setprecision(6)
                << result.structure.structure.length_scale << std::defaultfloat
                << " and read as hyperbolic lengths\n";
    }
    for (std::size_t c = 0; c < result.components.size(); ++c) {
      const ComponentFlow& comp = result.components[c];
      if (hyperbolic) {
        // Gauss-Bonnet in curvature -1: area = sum K - 2 pi chi.
        std::cout << "  component " << c << ": hyperbolic area " << std::setprecision(12)
                  << comp.flow.total_area << " = sum K - 2 pi chi up to " << std::setprecision(2)
                  << comp.flow.gauss_bonnet_relative_error << " (relative)" << std::defaultfloat
                  << "\n";
      }
      std::cout << "  component " << c << " (" << comp.vertices.size() << " vertices, genus "
                << comp.genus << ", " << comp.boundary_loops
                << " boundary loops): " << comp.flow.iterations << " iterations, "
                << (comp.flow.intrinsic.flips() > 0
                        ? std::to_string(comp.flow.intrinsic.flips()) + " edges flipped, "
                        : "")
                << std::fixed << std::setprecision(3) << comp.flow.timings.total
                << " s: " << cli::message_with_fixes(comp.flow.message, comp.flow.fixes)
                << std::defaultfloat << "\n";
    }
    if (!args.output.empty()) std::cout << "  wrote " << args.output << "\n";
  }
  return result.converged ? kOk : kNotConverged;
}

}  // namespace

Subcommand add_flow_command(CLI::App& app) {
  auto args = std::make_shared<FlowArgs>();
  CLI::App* cmd = app.add_subcommand(
      "flow", "Find the discrete conformal metric that realises a target curvature (Ricci flow).");
  cmd->add_option("MESH", args->mesh, "mesh file (.obj .off .ply .stl)")->required();
  cmd->add_option("--scheme", args->scheme,
                  "discrete metric: vertex-scaling (discrete conformal equivalence with "
                  "intrinsic Delaunay flips: reaches every admissible target), thurston (the "
                  "tutorial's circle packing), tangential, inversive-distance, virtual-radius")
      ->capture_default_str();
  cmd->add_option("--geometry", args->geometry,
                  "background geometry: euclidean (flat triangles) or hyperbolic (curvature -1; "
                  "the flat target then gives the uniformization metric of a surface with "
                  "chi < 0, with geodesic boundary)")
      ->capture_default_str();
  cmd->add_option("--init", args->init,
                  "initial circle packing (thurston, tangential): fit (least squares, tutorial "
                  "eq. 1) or unit (radii 1, Phi 0)")
      ->capture_default_str();
  cmd->add_option("--target", args->target,
                  "target curvature: natural (flat where the topology allows one: with "
                  "boundary, or a torus; uniform on other closed components; flat with "
                  "--cones), flat (zero but at --cones), free (flat, boundary radii fixed), "
                  "disk (boundary curvature 2 pi chi / m), disk-length (boundary curvature by "
                  "length), geodesic (boundary curvature 0), uniform (2 pi chi / n), or a file "
                  "with one value per vertex")
      ->capture_default_str();
  cmd->add_option("--boundary", args->boundary,
                  "boundary of a flat target: free (the euclidean default), disk, disk-length "
                  "or geodesic (the hyperbolic default)");
  cmd->add_option("--cones", args->cones,
                  "cone vertices (0-based, as in the file) and curvatures: a list such as "
                  "'12:pi/2,40:-pi' or a file of 'vertex curvature' lines");
  cmd->add_option("--solver", args->solver, "newton or gradient")->capture_default_str();
  cmd->add_option("--flips", args->flips,
                  "intrinsic Delaunay edge flips: auto (on for vertex-scaling, in either "
                  "geometry, which then reaches every target that satisfies Gauss-Bonnet), "
                  "off, or delaunay")
      ->capture_default_str();
  cmd->add_option("--tol", args->tolerance, "stop at max |K-bar - K| <= tol (radians)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--max-iterations", args->max_iterations,
                  "iteration limit (0: 200 for newton, 1000000 for gradient)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--step", args->step,
                  "gradient flow time step (0: 1 / largest Hessian diagonal, the stable step)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("-o,--output", args->output,
                  "write the result (per-vertex u, K, target; per-edge lengths; history) as "
                  "JSON");
  cmd->add_flag("--json", args->json, "print the summary as JSON");
  cmd->add_flag("--progress", args->progress, "print every iteration on stderr");
  add_input_options(cmd, args->input);

  return {cmd, [args] { return run_flow(*args); }};
}

}  // namespace ricci::cli
