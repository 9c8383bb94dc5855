#pragma once
/// \file
/// One program run in a child process of its own, with a wall-clock limit and a memory limit, so
/// that a crash, a hang or a memory blow-up ends that child and nothing else.

#include <string>
#include <vector>

namespace ricci {

/// Limits of a child process.
struct ChildLimits {
  /// Wall-clock limit in seconds; 0: none. Past it the child's process group gets SIGTERM (the
  /// `ricci` program then removes its temporary files), then SIGKILL after kill_grace_seconds.
  double timeout_seconds = 0;
  /// Address-space limit (RLIMIT_AS) in MiB; 0: none. An allocation past it fails in the child
  /// (`ricci` then exits with status 5, out of memory).
  double memory_limit_mb = 0;
  /// Seconds between SIGTERM and SIGKILL.
  double kill_grace_seconds = 2;
  /// Bytes of the child's standard error kept (its end).
  int stderr_bytes = 8192;
};

/// How a child ended.
enum class ChildEnd {
  Exited,       ///< exit status in exit_code
  Signaled,     ///< killed by a signal it did not handle (signal)
  TimedOut,     ///< stopped by the wall-clock limit
  SpawnFailed,  ///< fork or exec failed (spawn_error)
};

/// What run_child observed.
struct ChildResult {
  ChildEnd end = ChildEnd::SpawnFailed;
  int exit_code = -1;  ///< for Exited
  int signal = 0;      ///< for Signaled (and the signal that ended a TimedOut child)
  int pid = 0;
  double seconds = 0;       ///< wall clock from spawn to reaping
  long peak_memory_kb = 0;  ///< the child's maximum resident set size (getrusage)
  std::string stderr_text;  ///< the end of its standard error (ChildLimits::stderr_bytes)
  std::string spawn_error;  ///< for SpawnFailed
};

/// Runs argv[0] (a path; no PATH search) with argv in a new process group, its standard input
/// and output on /dev/null and its standard error captured; environment: this process's, with
/// each "NAME=value" of env_overrides set and each bare "NAME" removed. The child is sent
/// SIGTERM when the thread that started it dies (so a killed batch leaves no orphans).
/// Thread-safe: several threads may each run a child.
/// \throw InvalidInput when argv is empty or a limit is negative
ChildResult run_child(const std::vector<std::string>& argv,
                      const std::vector<std::string>& env_overrides, const ChildLimits& limits);

/// "SIGSEGV", "SIGKILL", ... ("signal N" for others).
std::string signal_name(int signal);

}  // namespace ricci
