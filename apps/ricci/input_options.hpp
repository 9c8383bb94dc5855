#pragma once
/// \file
/// How the commands that read a mesh treat its defects: the options --repair[=MODE], --strict and
/// --largest-component, registered in one place for info, flow, param, sphere, spline and render
/// (and so checked by `ricci batch` with param's parser), and the read they ask for.

#include <string>

#include "ricci/mesh/io.hpp"

namespace CLI {
class App;
}  // namespace CLI

namespace ricci::cli {

/// The input options of one command.
struct InputArgs {
  /// --repair[=MODE]: auto (the default: repair a mesh with defects, with a warning; leave a
  /// mesh without them as it is), always (--repair: repair every mesh, duplicate positions
  /// welded too) or never (refuse a mesh with defects, as --strict)
  std::string repair = "auto";
  bool strict = false;             ///< --strict: --repair=never
  bool largest_component = false;  ///< --largest-component: repair, keep the largest component
};

/// The modes of --repair.
enum class RepairMode { Never, Auto, Always };

/// The mode the options ask for (--largest-component repairs always).
/// \throw InvalidInput when --largest-component meets --strict or --repair=never, with the fix
RepairMode repair_mode(const InputArgs& args);

/// Registers --repair[=MODE], --strict and --largest-component on `cmd`.
/// \param info_help for `ricci info`, which describes the file as it is by default
void add_input_options(CLI::App* cmd, InputArgs& args, bool info_help = false);

/// Reads the command's mesh as the options say: auto and always repair (ReadOptions::auto_repair,
/// ReadOptions::repair) and print what changed on stderr as it happens, auto as warnings;
/// never refuses a defective mesh, naming the option that would read it when repair makes it
/// valid ("try: drop --strict").
/// \param validate false for `ricci info`, which lists every defect instead of throwing
ReadResult read_input(const std::string& path, const InputArgs& args, bool validate = true);

/// The mode's name for the "repair" object of the JSON reports: "auto" or "always".
const char* repair_mode_name(RepairMode mode);

/// Prints what repair_mesh changed in `path` on stderr, one "repair: PATH: ..." line per change
/// (or "nothing to repair"); as warnings, after a line saying the file had defects, when
/// `automatic` (the auto mode repaired it unasked).
void print_repair(const std::string& path, const RepairReport& report, bool automatic = false);

}  // namespace ricci::cli
