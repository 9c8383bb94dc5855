// The `ricci` command line: discrete surface Ricci flow on triangle meshes.
#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <vector>

#include "batch_command.hpp"
#include "commands.hpp"
#include "fixes.hpp"
#include "param_command.hpp"
#include "ricci/errors.hpp"
#include "ricci/mesh/io.hpp"
#include "ricci/numerics/sparse_cholesky.hpp"
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

  // In the order `ricci --help` lists them.
  std::vector<Subcommand> commands;
  commands.push_back(add_info_command(app));
  commands.push_back(add_flow_command(app));
  commands.push_back(add_param_command(app));
#ifdef RICCI_HAVE_RENDER
  commands.push_back(add_render_command(app));
  commands.push_back(add_view_command(app));
#endif
  commands.push_back(add_sphere_command(app));
  commands.push_back(add_spline_command(app));
  commands.push_back(add_match_command(app));
  commands.push_back(add_morph_command(app));
  commands.push_back(add_batch_command(app, argv[0]));
  commands.push_back(add_generate_command(app));
#ifdef RICCI_HAVE_BLENDER_ADDON
  commands.push_back(add_blender_addon_command(app, argv[0]));
#endif

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kOk : kBadInput;
  }
  try {
    for (const Subcommand& command : commands) {
      if (*command.command) return command.run();
    }
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
  // Before anything else: OpenBLAS's worker threads spin for their first 0.1 s, a core's worth
  // on two cores, and ricci never gives them work (sparse_cholesky.hpp).
  ricci::SparseCholesky::release_blas_threads();
  // What escapes run_main's own handlers (building the option parser, say) is a bug too.
  try {
    return run_main(argc, argv);
  } catch (...) {
    std::fputs("internal error: an exception escaped the command line\n", stderr);
    return ricci::cli::kInternalError;
  }
}
