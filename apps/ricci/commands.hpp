#pragma once
/// \file
/// The subcommands of the `ricci` program. Each fills its options from the command line, runs the
/// library and returns an exit code; errors propagate as ricci exceptions to main.

#include <string>
#include <vector>

#include "input_options.hpp"
#include "ricci/param/cones/cones.hpp"

namespace CLI {
class App;
}  // namespace CLI

namespace ricci::cli {

/// Exit codes of the `ricci` program (documented in README.md).
enum ExitCode : int {
  kOk = 0,
  kBadInput = 2,  ///< unreadable or defective mesh, inadmissible target, bad option
  /// the flow stopped before reaching the tolerance, including a numerical breakdown (the
  /// linear algebra failed on a degenerating metric: FlowStatus::SolverFailed or SolverError);
  /// for `sphere` also a map that fails its own checks (SphereResult::valid)
  kNotConverged = 3,
  kInternalError = 4,  ///< a bug: an exception no other code covers
  kOutOfMemory = 5,    ///< an allocation failed (a memory limit, or the machine's memory)
  kSomeFailed = 6,     ///< batch: at least one mesh did not end Ok (the summary lists them)
};

struct InfoArgs {
  std::string mesh;
  bool json = false;
  InputArgs input;  ///< --repair[=MODE], --strict, --largest-component (input_options.hpp)
};
int run_info(const InfoArgs& args);

struct FlowArgs {
  std::string mesh;
  InputArgs input;  ///< --repair[=MODE], --strict, --largest-component (input_options.hpp)
  std::string scheme = "vertex-scaling";
  std::string geometry = "euclidean";
  std::string init = "fit";
  std::string target = "natural";
  std::string boundary;  ///< empty: free (euclidean) or geodesic (hyperbolic)
  std::string cones;
  std::string solver = "newton";
  std::string flips = "auto";
  double tolerance = 1e-10;
  int max_iterations = 0;
  double step = 0;
  std::string output;
  bool json = false;
  bool progress = false;
};
int run_flow(const FlowArgs& args);

struct ParamArgs {
  std::string mesh;
  InputArgs input;  ///< --repair[=MODE], --strict, --largest-component (input_options.hpp)
  std::string output;
  std::string cones = "needed";
  std::string boundary = "free";
  std::string scheme = "vertex-scaling";
  std::string flips = "auto";
  std::string report;
  bool quantize = false;
  double max_log_scale = 1.0;
  int max_cones = 0;
  double cone_smoothness = ConeSelectionOptions{}.smoothness;
  std::string polish = "angles";  ///< --polish: "angles" (PolishOptions) or "none"
  /// --fold-free: "charts" (untangle, then charts where the exact map still fails), "untangle"
  /// (untangle only) or "none" (the exact map as it is): FoldFreeOptions.
  std::string fold_free = "charts";
  double tolerance = 1e-12;
  bool json = false;
  bool progress = false;
  std::string pictures;  ///< --pictures: folder for the pictures (render_command.hpp)
  std::string geometry = "euclidean";
  /// --faces: "input" (the input's faces, linear uv) or "refinement" (the common refinement
  /// with homogeneous uv, ricci/param/refinement/common_refinement.hpp, and its companion files)
  std::string faces = "input";
  double gutter = 0.002;  ///< --gutter (ChartPackingOptions::gutter)
  /// --texture: "checker" (STEM.png beside the OBJ), "none" (no material), or an image file
  std::string texture = "checker";
  std::string format;  ///< --format: obj or glb; empty: from -o's extension
  /// --fault (hidden; honoured only when RICCI_FAULT_INJECTION=1): segv, abort, hang or alloc,
  /// the failures `ricci batch` must survive, injected for its tests.
  std::string fault;
};
/// Registers `param` and its options on app (also used by `batch` to check the options it
/// passes on).
CLI::App* add_param_subcommand(CLI::App& app, ParamArgs& param);
/// What `ricci batch` and `ricci.batch` check before running anything: every option is one that
/// `ricci param` parses, and none is one that batch sets itself (-o, --report, --json,
/// --progress, --pictures). \param where names their origin in the message; \param outputs
/// names where the outputs go ("the -o folder"). \throw InvalidInput naming the option
void check_param_options(const std::vector<std::string>& options, const std::string& where,
                         const std::string& outputs);
int run_param(const ParamArgs& args);

struct SphereArgs {
  std::string mesh;
  InputArgs input;  ///< --repair[=MODE], --strict, --largest-component (input_options.hpp)
  std::string output;
  std::string scheme = "vertex-scaling";
  std::string flips = "auto";
  int pole = -1;  ///< file vertex index; -1: automatic
  double tolerance = 1e-12;
  bool untangle = true;  ///< --no-untangle: SphereOptions::untangle off
  std::string report;
  bool json = false;
  bool progress = false;
};
int run_sphere(const SphereArgs& args);

struct SplineArgs {
  std::string mesh;
  InputArgs input;           ///< --repair[=MODE], --strict, --largest-component (input_options.hpp)
  std::string output;        ///< the spline surface (.obj)
  std::string control_net;   ///< --control-net: the control net (.obj), optional
  int refine = 2;            ///< SplineOptions::refine
  double smoothness = 1e-4;  ///< SplineOptions::smoothness
  /// --cones as for param; empty: by topology (none with boundary or genus 1, auto otherwise)
  std::string cones;
  std::string scheme = "vertex-scaling";
  std::string flips = "auto";
  double tolerance = 1e-12;
  std::string report;
  bool json = false;
  bool progress = false;
  std::string pictures;  ///< --pictures: folder for the pictures (render_command.hpp)
};
int run_spline(const SplineArgs& args);

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
int run_generate(const GenerateArgs& args);

}  // namespace ricci::cli
