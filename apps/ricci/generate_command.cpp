// `ricci generate`: the built-in example meshes and hard cases.
#include <CLI/CLI.hpp>
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/hard_cases.hpp"
#include "ricci/mesh/io.hpp"

namespace ricci::cli {
namespace {

struct GenerateArgs {
  std::string kind;
  std::string output;
  double needles = 0;     ///< --needles: pull_vertices_to_neighbours amount (0: none)
  bool valence3 = false;  ///< --valence3: split_faces_near_corner
  int resolution = 0;     ///< 0: the kind's default
  int genus = 2;
  int holes = 0;
  int fingers = 5;             ///< --fingers: make_ball_with_fingers count
  double finger_length = 3.0;  ///< --finger-length: a finger's length over its circumference
};

int run_generate(const GenerateArgs& args) {
  const int r = args.resolution;
  Mesh mesh;
  if (args.kind == "tetrahedron") {
    mesh = make_tetrahedron(1.0);
  } else if (args.kind == "icosphere") {
    mesh = make_icosphere(r > 0 ? r : 3);
  } else if (args.kind == "disk") {
    mesh = make_disk(r > 0 ? r : 16, 0.5);
  } else if (args.kind == "torus") {
    mesh = make_torus(r > 0 ? 2 * r : 64, r > 0 ? r : 32);
  } else if (args.kind == "surface") {
    mesh = args.holes > 0 ? make_surface_with_holes(args.genus, args.holes, r > 0 ? r : 24)
                          : make_closed_surface(args.genus, r > 0 ? r : 24);
  } else if (args.kind == "cad-cylinder") {
    mesh = make_cad_cylinder(r > 0 ? r : 360);
  } else if (args.kind == "cad-ring") {
    mesh = make_cad_ring(r > 0 ? r : 360);
  } else if (args.kind == "fingers") {
    mesh = make_ball_with_fingers(args.fingers, args.finger_length, r > 0 ? r : 16);
  } else {
    throw InvalidInput("generate: unknown kind '" + args.kind +
                       "'; expected tetrahedron, icosphere, disk, torus, surface, cad-cylinder, "
                       "cad-ring or fingers");
  }
  if (args.valence3) mesh = split_faces_near_corner(mesh, 0.05, 0.05, 3);
  if (args.needles > 0) mesh = pull_vertices_to_neighbours(mesh, args.needles, 1, 2);
  write_obj(args.output, mesh);
  std::cout << "wrote " << args.output << ": " << mesh.num_vertices() << " vertices, "
            << mesh.num_faces() << " faces\n";
  return kOk;
}

}  // namespace

Subcommand add_generate_command(CLI::App& app) {
  auto args = std::make_shared<GenerateArgs>();
  CLI::App* cmd = app.add_subcommand(
      "generate",
      "Write a built-in example mesh: tetrahedron, icosphere, disk, torus, surface, or a hard "
      "case (cad-cylinder, cad-ring: CAD strips and fans; fingers: a ball with long thin "
      "fingers), optionally made harder still "
      "(--needles, --valence3).");
  cmd->add_option("KIND", args->kind,
                  "tetrahedron, icosphere, disk, torus, surface, cad-cylinder, cad-ring, fingers")
      ->required();
  cmd->add_option("-o,--output", args->output, "output .obj file")->required();
  cmd->add_option("--resolution", args->resolution,
                  "detail (icosphere: subdivisions; disk: rings; torus: minor segments; "
                  "surface: cells along its length; fingers: cells along a side of the ball's "
                  "cube, even); 0 for the default")
      ->capture_default_str();
  cmd->add_option("--genus", args->genus, "genus of `surface`")->capture_default_str();
  cmd->add_option("--holes", args->holes, "boundary loops cut into `surface`")
      ->capture_default_str();
  cmd->add_option("--needles", args->needles,
                  "pull every other interior vertex this fraction (0..1) of the way to a "
                  "neighbour: scan-like needles (0.998: angles of about 0.1 degree)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 0.9999));
  cmd->add_option("--fingers", args->fingers, "fingers of `fingers` (0 to 6)")
      ->capture_default_str();
  cmd->add_option("--finger-length", args->finger_length,
                  "length of each finger of `fingers` over its circumference (a conformal map "
                  "shrinks the tips' area by about exp(-4 pi times this))")
      ->capture_default_str();
  cmd->add_flag("--valence3", args->valence3,
                "split every third face 1-to-3 near a corner, the new vertex lifted off "
                "the surface: valence-3 vertices and needles");

  return {cmd, [args] { return run_generate(*args); }};
}

}  // namespace ricci::cli
