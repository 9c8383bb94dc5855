#pragma once
/// \file
/// The command line's phrasing of the library's OptionFix (ricci/errors.hpp): each option as its
/// flag, "try: --cones auto, or --cones one". The one place the CLI phrases them, for refusals
/// and for flows that stopped short alike.

#include <string>
#include <vector>

#include "ricci/errors.hpp"

namespace ricci::cli {

/// "try: --flips delaunay, or --scheme vertex-scaling"; empty when there are none.
inline std::string phrase_fixes(const std::vector<OptionFix>& fixes) {
  std::string out;
  for (std::size_t i = 0; i < fixes.size(); ++i) {
    out += (i == 0 ? "try: --" : ", or --") + fixes[i].option + " " + fixes[i].value;
  }
  return out;
}

/// A message with its fixes phrased on a line of their own, indented.
inline std::string message_with_fixes(const std::string& message,
                                      const std::vector<OptionFix>& fixes) {
  return fixes.empty() ? message : message + "\n  " + phrase_fixes(fixes);
}

}  // namespace ricci::cli
