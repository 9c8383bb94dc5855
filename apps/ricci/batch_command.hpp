#pragma once
/// \file
/// `ricci batch`: many meshes through `ricci param`, each in a child process with limits, on
/// local workers or MPI ranks (batch_mpi.hpp), resumable from its results log.

#include <string>
#include <vector>

#include "commands.hpp"

namespace CLI {
class App;
}  // namespace CLI

namespace ricci::cli {

struct BatchArgs {
  std::string input;                       ///< folder or manifest
  std::string output;                      ///< -o: the output folder
  int jobs = 0;                            ///< --jobs: local workers (0: the machine's cores)
  double timeout = 0;                      ///< --timeout, seconds per mesh (0: none)
  double memory_limit = 0;                 ///< --memory-limit, MiB per mesh (0: none)
  int threads = 0;                         ///< --threads per mesh (0: cores / jobs)
  bool retry_failed = false;               ///< --retry-failed
  bool progress = false;                   ///< --progress: a line per mesh
  bool json = false;                       ///< --json: print the summary as JSON
  std::vector<std::string> param_options;  ///< everything else: passed to `ricci param`
};

/// Registers `batch`; the options it does not know are collected for `ricci param`.
CLI::App* add_batch_subcommand(CLI::App& app, BatchArgs& args);

/// Runs the batch (locally, or as one rank of an MPI launch); the exit code: 0 when every mesh
/// is Ok, kSomeFailed otherwise.
/// \param argv0 the program's own argv[0] (used when /proc/self/exe cannot be read)
int run_batch_command(BatchArgs& args, const CLI::App& command, const std::string& argv0);
/// `ricci batch` as a Subcommand of the program; \param argv0 as for run_batch_command.
Subcommand add_batch_command(CLI::App& app, const std::string& argv0);

}  // namespace ricci::cli
