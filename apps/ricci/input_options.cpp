#include "input_options.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <iostream>
#include <vector>

#include "ricci/errors.hpp"

namespace ricci::cli {
namespace {

constexpr const char* kRepairHelp =
    "what to do with a mesh that has defects repair can fix (duplicate faces and vertices, "
    "faces using a vertex twice, zero-area slivers, non-manifold edges and vertices, "
    "inconsistent orientation): auto (the default) repairs such a mesh and says what changed on "
    "stderr as warnings, and in the \"repair\" object of --json / --report; a mesh without "
    "defects is read as it is; --repair (=always) repairs every mesh (equal positions welded "
    "too); --repair=never refuses a defective mesh, as --strict";
constexpr const char* kInfoRepairHelp =
    "auto (the default): describe the file as it is, list its defects and say what the other "
    "commands' repair would change and whether the mesh is valid afterwards; --repair "
    "(=always): describe the repaired mesh (what changed on stderr); --repair=never: the "
    "defects only, as --strict";
constexpr const char* kStrictHelp =
    "refuse a mesh with defects (exit 2, the first defect named with its file position), as "
    "--repair=never (not with --repair)";
constexpr const char* kInfoStrictHelp =
    "the file's defects only, without what repair would change, as --repair=never (not with "
    "--repair)";
constexpr const char* kLargestComponentHelp =
    "repair the mesh and keep only its connected component with the most faces (param takes "
    "one component)";

/// The fixes a refusal of the never mode names: the mode that reads the file.
std::vector<OptionFix> reading_fixes(const InputArgs& args) {
  return args.strict ? fixes_of({{"strict", "false"}}) : fixes_of({{"repair", "auto"}});
}

}  // namespace

RepairMode repair_mode(const InputArgs& args) {
  const RepairMode mode = args.strict || args.repair == "never" ? RepairMode::Never
                          : args.repair == "always"             ? RepairMode::Always
                                                                : RepairMode::Auto;
  if (args.largest_component && mode == RepairMode::Never) {
    throw InvalidInput(std::string("--largest-component repairs the mesh, which ") +
                           (args.strict ? "--strict" : "--repair=never") + " forbids",
                       reading_fixes(args));
  }
  return args.largest_component ? RepairMode::Always : mode;
}

const char* repair_mode_name(RepairMode mode) {
  switch (mode) {
    case RepairMode::Never:
      return "never";
    case RepairMode::Auto:
      return "auto";
    case RepairMode::Always:
      return "always";
  }
  return "auto";
}

void add_input_options(CLI::App* cmd, InputArgs& args, bool info_help) {
  // A flag with an optional value: `--repair` alone means always, `--repair=MODE` names one; a
  // flag never takes the next word, so `--repair MESH` reads MESH as before.
  const CLI::Validator mode(
      [](std::string& value) -> std::string {
        if (value == "true") value = "always";
        if (value == "always" || value == "auto" || value == "never") return {};
        return "expected --repair, --repair=always, --repair=auto or --repair=never, not '" +
               value + "'";
      },
      "", "repair mode");
  CLI::Option* repair =
      cmd->add_flag("--repair", args.repair, info_help ? kInfoRepairHelp : kRepairHelp)
          ->transform(mode)
          ->option_text("[=MODE]");
  // (option_text: the help line without CLI11's "Excludes: --repair", which kStrictHelp says.)
  CLI::Option* strict =
      cmd->add_flag("--strict", args.strict, info_help ? kInfoStrictHelp : kStrictHelp)
          ->option_text(" ");
  repair->excludes(strict);
  cmd->add_flag("--largest-component", args.largest_component, kLargestComponentHelp);
}

void print_repair(const std::string& path, const RepairReport& report, bool automatic) {
  if (automatic) {
    std::cerr << "warning: " << path
              << ": repairing: the mesh has defects (--strict refuses such a mesh instead):\n";
    for (const std::string& m : report.messages) {
      std::cerr << "warning: repair: " << path << ": " << m << "\n";
    }
    return;
  }
  if (report.messages.empty()) std::cerr << "repair: " << path << ": nothing to repair\n";
  for (const std::string& m : report.messages) std::cerr << "repair: " << path << ": " << m << "\n";
}

ReadResult read_input(const std::string& path, const InputArgs& args, bool validate) {
  const RepairMode mode = repair_mode(args);
  ReadOptions options;
  options.validate = validate;
  options.repair = mode == RepairMode::Always;
  options.auto_repair = mode == RepairMode::Auto;
  options.repair_options.largest_component_only = args.largest_component;
  // The changes are printed as soon as they are made, before validation (which may still refuse
  // what repair cannot fix).
  const bool automatic = mode == RepairMode::Auto;
  options.on_repair = [path, automatic](const RepairReport& report) {
    print_repair(path, report, automatic);
  };
  // The library names ReadOptions::repair where repair makes the mesh valid; here the option
  // that reads it is leaving the never mode.
  const OptionFix library_fix{"repair", "true"};
  auto repairable = [&](const InvalidInput& e) {
    return mode == RepairMode::Never &&
           std::find(e.fixes().begin(), e.fixes().end(), library_fix) != e.fixes().end();
  };
  try {
    return read_mesh(path, options);
  } catch (const TopologyError& e) {
    if (!repairable(e)) throw;
    throw TopologyError(e.what(), reading_fixes(args));
  } catch (const InvalidInput& e) {
    if (!repairable(e)) throw;
    throw InvalidInput(e.what(), reading_fixes(args));
  }
}

}  // namespace ricci::cli
