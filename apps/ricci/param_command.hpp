#pragma once
/// \file
/// `ricci param`: its arguments, its options (param_options.cpp, also read by `batch` to check the
/// options it passes on) and its run (param_command.cpp).

#include <string>
#include <vector>

#include "commands.hpp"
#include "input_options.hpp"
#include "ricci/param/parameterize.hpp"

namespace ricci::cli {

struct ParamArgs {
  std::string mesh;
  InputArgs input;  ///< --repair[=MODE], --strict, --largest-component (input_options.hpp)
  std::string output;
  std::string cones = cone_mode_name(ParamOptions{}.cone_mode);
  std::string boundary = boundary_mode_name(ParamOptions{}.boundary);
  std::string seams = seam_mode_name(ParamOptions{}.seams);
  std::string scheme = scheme_name(ParamOptions{}.structure.scheme);
  std::string flips = edge_flips_name(ParamOptions{}.flow.flips);
  std::string report;
  bool quantize = ParamOptions{}.quantize;
  double max_log_scale = ParamOptions{}.auto_cones.max_log_scale;
  int max_cones = ParamOptions{}.auto_cones.max_cones;
  double cone_smoothness = ParamOptions{}.auto_cones.smoothness;
  /// --polish: "angles" (PolishOptions) or "none"
  std::string polish = ParamOptions{}.polish.enabled ? "angles" : "none";
  /// --fold-free: "charts" (untangle, then charts where the exact map still fails), "untangle"
  /// (untangle only) or "none" (the exact map as it is): FoldFreeOptions.
  std::string fold_free = ParamOptions{}.fold_free.charts     ? "charts"
                          : ParamOptions{}.fold_free.untangle ? "untangle"
                                                              : "none";
  double tolerance = ParamOptions{}.flow.tolerance;
  bool json = false;
  bool progress = false;
  std::string pictures;  ///< --pictures: folder for the pictures (render_command.hpp)
  std::string geometry = geometry_name(ParamOptions{}.structure.geometry);
  /// --faces: "input" (the input's faces, linear uv) or "refinement" (the common refinement
  /// with homogeneous uv, ricci/param/refinement/common_refinement.hpp, and its companion files)
  std::string faces = "input";
  double gutter = ParamOptions{}.packing.gutter;  ///< --gutter (ChartPackingOptions::gutter)
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
/// `ricci param` as a Subcommand of the program.
Subcommand add_param_command(CLI::App& app);

}  // namespace ricci::cli
