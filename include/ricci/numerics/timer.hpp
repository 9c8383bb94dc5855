#pragma once
/// \file
/// The one clock of the library's reports: every `seconds` and `timings` field is wall time
/// measured with `Clock` (steady, so that a clock adjustment never yields a negative time).

#include <chrono>

namespace ricci {

using Clock = std::chrono::steady_clock;

/// Seconds elapsed since `start`, in double.
inline double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace ricci
