// The `ricci` command line: discrete surface Ricci flow on triangle meshes.
#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>
#include <iostream>

#include "batch_command.hpp"
#include "commands.hpp"
#include "fixes.hpp"
#include "ricci/errors.hpp"
#include "ricci/mesh/io.hpp"
#ifdef RICCI_HAVE_RENDER
#include "render_command.hpp"
#endif

#ifndef RICCI_VERSION
#define RICCI_VERSION "unknown"
#endif

namespace {

/// SIGINT/SIGTERM: remove the temporary files of writes in progress, then die of the signal with
/// its default action (exit status 128 + signal). Installed with SA_RESETHAND, so raise() finds
/// the default action; only async-signal-safe calls here.
extern "C" void remove_temporaries_and_die(int signal_number) {
  ricci::remove_pending_temporary_files();
  std::raise(signal_number);
}

/// Installs the handler for SIGINT and SIGTERM, except where the signal was ignored when the
/// program started (as for background jobs of a non-interactive shell): it stays ignored.
void install_interrupt_handlers() {
  for (const int signal_number : {SIGINT, SIGTERM}) {
    struct sigaction previous {};
    if (sigaction(signal_number, nullptr, &previous) != 0) continue;
    if (previous.sa_handler == SIG_IGN) continue;
    struct sigaction action {};
    action.sa_handler = remove_temporaries_and_die;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESETHAND;
    sigaction(signal_number, &action, nullptr);
  }
}

}  // namespace

namespace {

int run_main(int argc, char** argv) {
  using namespace ricci::cli;
  install_interrupt_handlers();
  CLI::App app{
      "ricci: discrete surface Ricci flow and conformal metrics on triangle meshes.\n"
      "Reads OBJ, OFF, PLY and STL. Exit codes: 0 ok, 2 bad input, 3 not converged (or a "
      "numerical breakdown), 4 internal error, 5 out of memory, 6 (batch) some mesh failed."};
  app.set_version_flag("--version", std::string("ricci ") + RICCI_VERSION);
  app.require_subcommand(1);

  InfoArgs info;
  CLI::App* info_cmd = app.add_subcommand(
      "info",
      "Print counts, topology (components, boundary loops, Euler characteristic, genus), "
      "the smallest angle and every defect of a mesh file as it is, and what the repair of the "
      "other commands (their default --repair=auto) would change; exit 2 when the file has "
      "defects, even ones repair fixes. --repair describes the repaired mesh instead.");
  info_cmd->add_option("MESH", info.mesh, "mesh file (.obj .off .ply .stl)")->required();
  info_cmd->add_flag("--json", info.json, "print the summary as JSON");
  add_input_options(info_cmd, info.input, true);

  FlowArgs flow;
  CLI::App* flow_cmd = app.add_subcommand(
      "flow", "Find the discrete conformal metric that realises a target curvature (Ricci flow).");
  flow_cmd->add_option("MESH", flow.mesh, "mesh file (.obj .off .ply .stl)")->required();
  flow_cmd
      ->add_option("--scheme", flow.scheme,
                   "discrete metric: vertex-scaling (discrete conformal equivalence with "
                   "intrinsic Delaunay flips: reaches every admissible target), thurston (the "
                   "tutorial's circle packing), tangential, inversive-distance, virtual-radius")
      ->capture_default_str();
  flow_cmd
      ->add_option("--geometry", flow.geometry,
                   "background geometry: euclidean (flat triangles) or hyperbolic (curvature -1; "
                   "the flat target then gives the uniformization metric of a surface with "
                   "chi < 0, with geodesic boundary)")
      ->capture_default_str();
  flow_cmd
      ->add_option("--init", flow.init,
                   "initial circle packing (thurston, tangential): fit (least squares, tutorial "
                   "eq. 1) or unit (radii 1, Phi 0)")
      ->capture_default_str();
  flow_cmd
      ->add_option("--target", flow.target,
                   "target curvature: natural (flat where the topology allows one: with "
                   "boundary, or a torus; uniform on other closed components; flat with "
                   "--cones), flat (zero but at --cones), free (flat, boundary radii fixed), "
                   "disk (boundary curvature 2 pi chi / m), disk-length (boundary curvature by "
                   "length), geodesic (boundary curvature 0), uniform (2 pi chi / n), or a file "
                   "with one value per vertex")
      ->capture_default_str();
  flow_cmd->add_option("--boundary", flow.boundary,
                       "boundary of a flat target: free (the euclidean default), disk, disk-length "
                       "or geodesic (the hyperbolic default)");
  flow_cmd->add_option("--cones", flow.cones,
                       "cone vertices (0-based, as in the file) and curvatures: a list such as "
                       "'12:pi/2,40:-pi' or a file of 'vertex curvature' lines");
  flow_cmd->add_option("--solver", flow.solver, "newton or gradient")->capture_default_str();
  flow_cmd
      ->add_option("--flips", flow.flips,
                   "intrinsic Delaunay edge flips: auto (on for vertex-scaling, in either "
                   "geometry, which then reaches every target that satisfies Gauss-Bonnet), "
                   "off, or delaunay")
      ->capture_default_str();
  flow_cmd->add_option("--tol", flow.tolerance, "stop at max |K-bar - K| <= tol (radians)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  flow_cmd
      ->add_option("--max-iterations", flow.max_iterations,
                   "iteration limit (0: 200 for newton, 1000000 for gradient)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  flow_cmd
      ->add_option("--step", flow.step,
                   "gradient flow time step (0: 1 / largest Hessian diagonal, the stable step)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  flow_cmd->add_option("-o,--output", flow.output,
                       "write the result (per-vertex u, K, target; per-edge lengths; history) as "
                       "JSON");
  flow_cmd->add_flag("--json", flow.json, "print the summary as JSON");
  flow_cmd->add_flag("--progress", flow.progress, "print every iteration on stderr");
  add_input_options(flow_cmd, flow.input);

  ParamArgs param;
  CLI::App* param_cmd = add_param_subcommand(app, param);
#ifdef RICCI_HAVE_RENDER
  RenderArgs render;
  CLI::App* render_cmd = add_render_subcommand(app, render);
  ViewArgs view;
  CLI::App* view_cmd = add_view_subcommand(app, view);
#endif

  SphereArgs sphere;
  CLI::App* sphere_cmd = app.add_subcommand(
      "sphere",
      "Spherical conformal map of a closed genus-0 mesh: every vertex on the unit sphere, no "
      "inverted face, the centre of mass of the area at the origin; writes an OBJ with the "
      "input's faces (docs/sphere.md). A map that keeps an inverted face (a limb squeezed below "
      "double precision, a fold untangling cannot free) exits with code 3 and writes no OBJ.");
  sphere_cmd->add_option("MESH", sphere.mesh, "mesh file (.obj .off .ply .stl)")->required();
  sphere_cmd->add_option("-o,--output", sphere.output, "output .obj (vertices on the sphere)")
      ->required();
  sphere_cmd->add_option("--scheme", sphere.scheme, "discrete metric (see ricci flow --help)")
      ->capture_default_str();
  sphere_cmd->add_option("--flips", sphere.flips, "intrinsic Delaunay edge flips of the flow")
      ->capture_default_str();
  sphere_cmd
      ->add_option("--pole", sphere.pole,
                   "vertex (0-based file index) removed for the flow; -1: the flattest vertex of "
                   "valence >= 5")
      ->capture_default_str();
  sphere_cmd->add_option("--tol", sphere.tolerance, "flow tolerance on max |K-bar - K|")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  sphere_cmd->add_flag("!--no-untangle", sphere.untangle,
                       "keep the exact map where it inverts a face instead of moving the vertex "
                       "into its star (see docs/sphere.md)");
  sphere_cmd->add_option("--report", sphere.report,
                         "write a JSON report: invariants, normalisation, distortion, flow, "
                         "precision (written also when the map fails its checks)");
  sphere_cmd->add_flag("--json", sphere.json, "print the report as JSON");
  sphere_cmd->add_flag("--progress", sphere.progress, "print flow iterations on stderr");
  add_input_options(sphere_cmd, sphere.input);

  SplineArgs spline;
  CLI::App* spline_cmd = app.add_subcommand(
      "spline",
      "Manifold spline: a C1 quadratic Powell-Sabin spline over the flat metric with cones, "
      "fitted to the mesh's positions; writes the spline surface as a triangle mesh "
      "(docs/splines.md).");
  spline_cmd->add_option("MESH", spline.mesh, "mesh file (.obj .off .ply .stl)")->required();
  spline_cmd->add_option("-o,--output", spline.output, "output .obj: the spline surface")
      ->required();
  spline_cmd->add_option("--control-net", spline.control_net,
                         "also write the control net (Bezier ordinates) as an .obj");
  spline_cmd->add_option("--refine", spline.refine, "each quadratic piece split K x K")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  spline_cmd
      ->add_option("--smooth", spline.smoothness,
                   "dimensionless weight of the smoothness term (Hessian jumps)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  spline_cmd->add_option("--cones", spline.cones,
                         "as for param; default: none with boundary or genus 1, auto otherwise");
  spline_cmd->add_option("--scheme", spline.scheme, "discrete metric (see ricci flow --help)")
      ->capture_default_str();
  spline_cmd->add_option("--flips", spline.flips, "intrinsic Delaunay edge flips of the flow")
      ->capture_default_str();
  spline_cmd->add_option("--tol", spline.tolerance, "flow tolerance on max |K-bar - K|")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  spline_cmd->add_option("--report", spline.report,
                         "write a JSON report: errors, C1 jumps, fit, timings, parameterization");
  spline_cmd->add_flag("--json", spline.json, "print the report as JSON");
  spline_cmd->add_flag("--progress", spline.progress, "print flow iterations on stderr");
  add_input_options(spline_cmd, spline.input);
#ifdef RICCI_HAVE_RENDER
  spline_cmd->add_option("--pictures", spline.pictures,
                         "write domain.png, control_net.png and surface.png (the three stages "
                         "from one camera) and layout.png (the flat layout with its cones) into "
                         "this folder (created when missing)");
#endif

  BatchArgs batch;
  CLI::App* batch_cmd = add_batch_subcommand(app, batch);

  GenerateArgs generate;
  CLI::App* generate_cmd = app.add_subcommand(
      "generate",
      "Write a built-in example mesh: tetrahedron, icosphere, disk, torus, surface, or a hard "
      "case (cad-cylinder, cad-ring: CAD strips and fans; fingers: a ball with long thin "
      "fingers), optionally made harder still "
      "(--needles, --valence3).");
  generate_cmd
      ->add_option("KIND", generate.kind,
                   "tetrahedron, icosphere, disk, torus, surface, cad-cylinder, cad-ring, fingers")
      ->required();
  generate_cmd->add_option("-o,--output", generate.output, "output .obj file")->required();
  generate_cmd
      ->add_option("--resolution", generate.resolution,
                   "detail (icosphere: subdivisions; disk: rings; torus: minor segments; "
                   "surface: cells along its length; fingers: cells along a side of the ball's "
                   "cube, even); 0 for the default")
      ->capture_default_str();
  generate_cmd->add_option("--genus", generate.genus, "genus of `surface`")->capture_default_str();
  generate_cmd->add_option("--holes", generate.holes, "boundary loops cut into `surface`")
      ->capture_default_str();
  generate_cmd
      ->add_option("--needles", generate.needles,
                   "pull every other interior vertex this fraction (0..1) of the way to a "
                   "neighbour: scan-like needles (0.998: angles of about 0.1 degree)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 0.9999));
  generate_cmd->add_option("--fingers", generate.fingers, "fingers of `fingers` (0 to 6)")
      ->capture_default_str();
  generate_cmd
      ->add_option("--finger-length", generate.finger_length,
                   "length of each finger of `fingers` over its circumference (a conformal map "
                   "shrinks the tips' area by about exp(-4 pi times this))")
      ->capture_default_str();
  generate_cmd->add_flag("--valence3", generate.valence3,
                         "split every third face 1-to-3 near a corner, the new vertex lifted off "
                         "the surface: valence-3 vertices and needles");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kOk : kBadInput;
  }
  try {
    if (*info_cmd) return run_info(info);
    if (*flow_cmd) return run_flow(flow);
    if (*param_cmd) return run_param(param);
    if (*sphere_cmd) return run_sphere(sphere);
    if (*spline_cmd) return run_spline(spline);
    if (*generate_cmd) return run_generate(generate);
    if (*batch_cmd) return run_batch_command(batch, *batch_cmd, argv[0]);
#ifdef RICCI_HAVE_RENDER
    if (*render_cmd) return run_render(render);
    if (*view_cmd) return run_view(view);
#endif
  } catch (const ricci::InvalidInput& e) {
    std::cerr << "error: " << e.what() << "\n";
    // The options that would have worked, as flags: "try: --cones auto, or --cones one".
    if (!e.fixes().empty()) std::cerr << "  " << ricci::cli::phrase_fixes(e.fixes()) << "\n";
    return kBadInput;
  } catch (const ricci::IoError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kBadInput;
  } catch (const ricci::SolverError& e) {
    // The linear algebra broke down on this input (a metric degenerating): the computation did
    // not converge, which is not a bug of the program.
    std::cerr << "error: numerical breakdown: " << e.what() << "\n";
    return kNotConverged;
  } catch (const std::bad_alloc&) {
    std::cerr << "error: out of memory\n";
    return kOutOfMemory;
  } catch (const std::exception& e) {
    std::cerr << "internal error: " << e.what() << "\n";
    return kInternalError;
  }
  return kInternalError;
}

}  // namespace

int main(int argc, char** argv) {
  // What escapes run_main's own handlers (building the option parser, say) is a bug too.
  try {
    return run_main(argc, argv);
  } catch (...) {
    std::fputs("internal error: an exception escaped the command line\n", stderr);
    return ricci::cli::kInternalError;
  }
}
