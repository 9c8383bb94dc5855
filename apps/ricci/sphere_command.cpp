// `ricci sphere`: the spherical conformal map of a closed genus-0 mesh.
#include <CLI/CLI.hpp>
#include <iostream>
#include <memory>

#include "command_support.hpp"
#include "commands.hpp"
#include "fixes.hpp"
#include "json_output.hpp"
#include "ricci/mesh/io.hpp"
#include "ricci/sphere/sphere.hpp"

namespace ricci::cli {
namespace {

struct SphereArgs {
  std::string mesh;
  InputArgs input;  ///< --repair[=MODE], --strict, --largest-component (input_options.hpp)
  std::string output;
  std::string scheme = scheme_name(SphereOptions{}.structure.scheme);
  std::string flips = edge_flips_name(SphereOptions{}.flow.flips);
  int pole = SphereOptions{}.pole;  ///< file vertex index; -1: automatic
  double tolerance = SphereOptions{}.flow.tolerance;
  bool untangle = SphereOptions{}.untangle;  ///< --no-untangle: SphereOptions::untangle off
  std::string report;
  bool json = false;
  bool progress = false;
};

int run_sphere(const SphereArgs& args) {
  SphereOptions options;
  options.structure.scheme = parse_scheme(args.scheme);
  options.flow.tolerance = args.tolerance;
  options.flow.flips = parse_edge_flips(args.flips);
  options.untangle = args.untangle;
  check_output_is_not_input(args.output, {args.mesh});
  if (!args.report.empty()) check_output_is_not_input(args.report, {args.mesh});

  const ReadResult read = read_input(args.mesh, args.input);
  print_warnings(read);
  if (args.pole >= 0) {
    const std::vector<int> to_mesh = inverse_map(read.vertex_map);
    if (args.pole >= static_cast<int>(to_mesh.size()) || to_mesh[args.pole] < 0) {
      throw InvalidInput("--pole: vertex " + std::to_string(args.pole) + " is not a vertex of " +
                         args.mesh + " used by any face");
    }
    options.pole = to_mesh[args.pole];
  }
  const SphereResult result =
      run_with_progress(args.mesh, args.progress, args.json, "sphere", options.flow,
                        [&] { return sphere_map(read.mesh, options); });
  nlohmann::json report = sphere_report(result, options);
  report["pole_file_index"] = read.vertex_map[result.pole];
  // The library's fixes name mesh vertices; --pole takes the file's.
  std::vector<OptionFix> fixes = result.fixes;
  for (OptionFix& fix : fixes) {
    if (fix.option == "pole") fix.value = std::to_string(read.vertex_map[std::stoi(fix.value)]);
  }
  std::string why = cli::message_with_fixes(result.message, fixes);
  if (result.converged && !result.valid) {
    // No option of sphere helps a map that inverts faces after untangling, or a limb squeezed
    // below double resolution; a cut parameterization with cones shrinks no limb.
    why += "\n  try: ricci param " + args.mesh + " -o OUT.obj (a parameterization with cones)";
  }
  if (!finish_report(args.mesh, args.output, args.report, read, args.input, report, result.valid,
                     why)) {
    return kNotConverged;
  }
  Mesh sphere;
  sphere.positions = result.positions;
  sphere.triangles = read.mesh.triangles;
  write_obj(args.output, sphere);
  if (args.json) {
    std::cout << report.dump(2) << "\n";
  } else {
    std::cout << args.mesh << " -> " << args.output << "\n"
              << "  pole " << read.vertex_map[result.pole] << ", flow "
              << result.flow.components.front().flow.iterations << " iterations, centring "
              << result.centre_iterations << " steps (|centre| " << result.centre_of_mass << ")\n"
              << "  inverted faces " << result.inverted_faces << ", area - 4 pi "
              << result.spherical_area - 4 * std::numbers::pi << ", angle distortion mean "
              << result.angle_distortion_mean << " max " << result.angle_distortion_max
              << ", log area [" << result.log_area_min << ", " << result.log_area_max << "]\n"
              << "  precision " << result.precision_bits << " bits (smallest altitude: plane "
              << result.min_plane_altitude << ", sphere " << result.min_sphere_altitude << "), "
              << result.unresolved_faces << " faces below double resolution, " << result.seconds
              << " s\n";
    if (!args.report.empty()) std::cout << "  wrote " << args.report << "\n";
  }
  return kOk;
}

}  // namespace

Subcommand add_sphere_command(CLI::App& app) {
  auto args = std::make_shared<SphereArgs>();
  CLI::App* cmd = app.add_subcommand(
      "sphere",
      "Spherical conformal map of a closed genus-0 mesh: every vertex on the unit sphere, no "
      "inverted face, the centre of mass of the area at the origin; writes an OBJ with the "
      "input's faces (docs/sphere.md). A map that keeps an inverted face (a limb squeezed below "
      "double precision, a fold untangling cannot free) exits with code 3 and writes no OBJ.");
  cmd->add_option("MESH", args->mesh, "mesh file (.obj .off .ply .stl)")->required();
  cmd->add_option("-o,--output", args->output, "output .obj (vertices on the sphere)")->required();
  cmd->add_option("--scheme", args->scheme, "discrete metric (see ricci flow --help)")
      ->capture_default_str();
  cmd->add_option("--flips", args->flips, "intrinsic Delaunay edge flips of the flow")
      ->capture_default_str();
  cmd->add_option("--pole", args->pole,
                  "vertex (0-based file index) removed for the flow; -1: the flattest vertex of "
                  "valence >= 5")
      ->capture_default_str();
  cmd->add_option("--tol", args->tolerance, "flow tolerance on max |K-bar - K|")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_flag("!--no-untangle", args->untangle,
                "keep the exact map where it inverts a face instead of moving the vertex "
                "into its star (see docs/sphere.md)");
  cmd->add_option("--report", args->report,
                  "write a JSON report: invariants, normalisation, distortion, flow, "
                  "precision (written also when the map fails its checks)");
  cmd->add_flag("--json", args->json, "print the report as JSON");
  cmd->add_flag("--progress", args->progress, "print flow iterations on stderr");
  add_input_options(cmd, args->input);

  return {cmd, [args] { return run_sphere(*args); }};
}

}  // namespace ricci::cli
