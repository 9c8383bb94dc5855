#pragma once
/// \file
/// What the benchmark programs share: wall-clock seconds and the process's peak memory.
#include <chrono>
#include <fstream>
#include <string>

namespace ricci::bench {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

/// Resets the kernel's peak resident set size of this process (Linux >= 4.0).
inline void reset_peak_memory() {
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5";
}

/// Peak resident set size of this process since the last reset, in MB (-1 when unknown).
inline double peak_memory_mb() {
  std::ifstream status("/proc/self/status");
  std::string key;
  while (status >> key) {
    if (key == "VmHWM:") {
      double kb = 0;
      status >> kb;
      return kb / 1024.0;
    }
    std::getline(status, key);
  }
  return -1;
}

}  // namespace ricci::bench
