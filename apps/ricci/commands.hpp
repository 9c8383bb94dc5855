#pragma once
/// \file
/// The subcommands of the `ricci` program, one file each (<name>_command.cpp): each registers its
/// options on the program's parser and returns how to run it. A run fills the library's options
/// from its arguments, runs the library and returns an exit code; errors propagate as ricci
/// exceptions to main, which turns them into messages and exit codes.

#include <functional>

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

/// A registered subcommand: its parser (true once the command line chose it) and its run.
struct Subcommand {
  CLI::App* command = nullptr;
  std::function<int()> run;
};

/// `ricci info` (info_command.cpp).
Subcommand add_info_command(CLI::App& app);
/// `ricci flow` (flow_command.cpp).
Subcommand add_flow_command(CLI::App& app);
/// `ricci sphere` (sphere_command.cpp).
Subcommand add_sphere_command(CLI::App& app);
/// `ricci spline` (spline_command.cpp).
Subcommand add_spline_command(CLI::App& app);
/// `ricci match` and `ricci morph` (match_command.cpp).
Subcommand add_match_command(CLI::App& app);
Subcommand add_morph_command(CLI::App& app);
/// `ricci generate` (generate_command.cpp).
Subcommand add_generate_command(CLI::App& app);
/// `ricci blender-addon` (blender_addon_command.cpp; built with libzip). argv0 locates the
/// installed Python module when /proc/self/exe cannot.
Subcommand add_blender_addon_command(CLI::App& app, const char* argv0);
// `param`: param_command.hpp; `batch`: batch_command.hpp; `render`, `view`: render_command.hpp.

}  // namespace ricci::cli
