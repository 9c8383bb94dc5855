#pragma once
/// \file
/// The command line's phrasing of the library's OptionFix (ricci/errors.hpp): each option as its
/// flag, "try: --cones auto, or --cones one". The one place the CLI phrases them, for refusals
/// and for flows that stopped short alike.

#include <string>
#include <vector>

#include "ricci/errors.hpp"

namespace ricci::cli {

/// One fix as the command line takes it: "--cones auto"; a flag turned on ("true") is the flag
/// alone, "--repair"; a flag turned off ("false") or an option unset (an empty value) is "drop
/// --strict", "drop --cones"; --repair, a flag with an optional value, takes it after "=":
/// "--repair=auto".
inline std::string phrase_fix(const OptionFix& fix) {
  if (fix.value == "true") return "--" + fix.option;
  if (fix.value == "false" || fix.value.empty()) return "drop --" + fix.option;
  if (fix.option == "repair") return "--repair=" + fix.value;
  return "--" + fix.option + " " + fix.value;
}

/// "try: --flips delaunay, or --scheme vertex-scaling"; empty when there are none. Each fix is
/// the option to add to the command (replacing the option's value where it is given already),
/// or the flag to drop.
inline std::string phrase_fixes(const std::vector<OptionFix>& fixes) {
  std::string out;
  for (std::size_t i = 0; i < fixes.size(); ++i) {
    out += (i == 0 ? "try: " : ", or ") + phrase_fix(fixes[i]);
  }
  return out;
}

/// A message with its fixes phrased on a line of their own, indented.
inline std::string message_with_fixes(const std::string& message,
                                      const std::vector<OptionFix>& fixes) {
  return fixes.empty() ? message : message + "\n  " + phrase_fixes(fixes);
}

}  // namespace ricci::cli
