#include "progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

namespace ricci::cli {

ProgressStyle choose_progress_style(bool lines_requested, bool json_output) {
  if (lines_requested) return ProgressStyle::Lines;
  if (!json_output && isatty(STDERR_FILENO)) return ProgressStyle::Bar;
  return ProgressStyle::Quiet;
}

FlowProgress make_progress(ProgressStyle style, const std::string& label, double tolerance) {
  if (style == ProgressStyle::Quiet) return {};
  if (style == ProgressStyle::Lines) {
    return [label](const IterationRecord& r) {
      std::fprintf(stderr, "  %s iteration %4d  max |K-bar - K| %.3e  step %.4g  %.2f s\n",
                   label.c_str(), r.iteration, r.max_error, r.step_length, r.seconds);
      return true;
    };
  }
  // The bar fills with log(e0 / e) / log(e0 / tol): Newton's last steps are the fast ones.
  auto first = std::make_shared<double>(-1);
  return [label, tolerance, first](const IterationRecord& r) {
    if (*first < 0) *first = std::max(r.max_error, tolerance * 10);
    const double span = std::log(*first / tolerance);
    double fraction = span > 0 ? std::log(*first / std::max(r.max_error, tolerance)) / span : 1.0;
    fraction = std::clamp(fraction, 0.0, 1.0);
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(std::lround(fraction * kWidth));
    char bar[kWidth + 1];
    for (int i = 0; i < kWidth; ++i) bar[i] = i < filled ? '#' : '.';
    bar[kWidth] = '\0';
    std::fprintf(stderr, "\r%s [%s] iteration %d, max |K-bar - K| %.2e, %.1f s   ", label.c_str(),
                 bar, r.iteration, r.max_error, r.seconds);
    std::fflush(stderr);
    return true;
  };
}

void finish_progress(ProgressStyle style) {
  if (style == ProgressStyle::Bar) std::fputc('\n', stderr);
}

}  // namespace ricci::cli
