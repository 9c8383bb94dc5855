#pragma once
/// \file
/// Progress reports of the command line: one line per iteration (--progress), or a single
/// self-updating bar when stderr is a terminal; nothing otherwise.

#include <string>

#include "ricci/flow/ricci_flow.hpp"

namespace ricci::cli {

/// How to show progress.
enum class ProgressStyle {
  Quiet,  ///< nothing
  Lines,  ///< one line per iteration on stderr
  Bar,    ///< one line rewritten in place (for terminals)
};

/// Lines when asked, a bar when stderr is a terminal and nothing else is printed there, quiet
/// otherwise.
ProgressStyle choose_progress_style(bool lines_requested, bool json_output);

/// A progress callback for the flow options. \param label e.g. "flow" or "param"
/// \param tolerance the flow's stopping tolerance (the bar fills on a log scale towards it)
FlowProgress make_progress(ProgressStyle style, const std::string& label, double tolerance);

/// Ends a bar line (prints the newline a bar leaves open); no-op for the other styles.
void finish_progress(ProgressStyle style);

}  // namespace ricci::cli
