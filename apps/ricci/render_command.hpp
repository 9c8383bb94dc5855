#pragma once
/// \file
/// The `render` subcommand (a textured OBJ to a PNG picture), the `view` subcommand (to an
/// interactive HTML page) and the pictures of `param --pictures DIR` and `spline --pictures DIR`.

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "input_options.hpp"
#include "ricci/hyperbolic/hyperbolic_param.hpp"
#include "ricci/param/parameterize.hpp"
#include "ricci/param/refinement/common_refinement.hpp"
#include "ricci/spline/manifold_spline.hpp"

namespace ricci::cli {

struct RenderArgs {
  std::string mesh;                       ///< OBJ with vt
  std::string output;                     ///< .png
  int width = 1024, height = 1024;        ///< pixels
  std::vector<std::string> view{"auto"};  ///< auto, x, -x, y, -y, z, -z, or three numbers
  std::vector<std::string> up;            ///< empty: automatic; else as view
  int checker = 16;                       ///< squares per texture unit
  int supersampling = 3;
  bool smooth = false;
  bool no_seams = false;
  bool no_cones = false;
  std::string uv_output;  ///< also the texture layout (.svg or .png)
  /// --repair[=MODE], --strict, --largest-component (input_options.hpp): repair_mesh on the
  /// geometry, texture corners following
  InputArgs input;
};

/// Adds `render` to the program; its flags fill `args`.
CLI::App* add_render_subcommand(CLI::App& app, RenderArgs& args);

int run_render(const RenderArgs& args);

struct ViewArgs {
  std::string mesh;                   ///< OBJ with vt (vt u v w: projective)
  std::string output;                 ///< .html
  std::string title;                  ///< empty: the mesh's file name
  double checker = 16;                ///< squares per texture unit when the page opens
  std::string colouring = "checker";  ///< checker, area or angle when the page opens
};

/// Adds `view` (a textured OBJ to an interactive HTML page) to the program.
CLI::App* add_view_subcommand(CLI::App& app, ViewArgs& args);

int run_view(const ViewArgs& args);

/// `ricci render` as a Subcommand of the program.
Subcommand add_render_command(CLI::App& app);
/// `ricci view` as a Subcommand of the program.
Subcommand add_view_command(CLI::App& app);

/// `param --pictures DIR`: writes the pictures of a parameterization into DIR and says so on
/// stderr; view.html (the web viewer, titled with `input`'s file name) shows `refinement` when
/// given (what `--faces refinement` writes), else the result's layout. No-op when `folder` is
/// empty.
void write_param_pictures(const std::string& folder, const MeshParamResult& result,
                          const std::string& input, const CommonRefinement* refinement = nullptr);

/// `param --geometry hyperbolic --pictures DIR`: tiling.svg and tiling.png, the fundamental
/// domain in the Poincare disk and its images under the group the segment maps generate.
void write_hyperbolic_pictures(const std::string& folder, const HyperbolicParamResult& result);

/// `spline --pictures DIR`: domain.png, control_net.png, surface.png (one camera) and
/// layout.png, said on stderr. No-op when `folder` is empty.
void write_manifold_spline_pictures(const std::string& folder, const SplineResult& result);

}  // namespace ricci::cli
