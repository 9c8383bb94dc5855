// run_child: exit statuses, signals, timeouts, standard error, environment and spawn failures,
// with /bin/sh as the child.
#include "ricci/batch/child_process.hpp"

#include <gtest/gtest.h>
#include <signal.h>

#include "ricci/errors.hpp"

namespace ricci {
namespace {

ChildResult sh(const std::string& script, const ChildLimits& limits = {},
               const std::vector<std::string>& env = {}) {
  return run_child({"/bin/sh", "-c", script}, env, limits);
}

/// Limits that stop the child after `timeout` seconds, with `grace` seconds between SIGTERM and
/// SIGKILL.
ChildLimits timeout_limits(double timeout, double grace) {
  ChildLimits limits;
  limits.timeout_seconds = timeout;
  limits.kill_grace_seconds = grace;
  return limits;
}

/// Seconds within which a timed-out child must have ended: its script sleeps 30 s, so ending
/// well before that shows the timeout stopped it, with room for a loaded machine.
constexpr double kTimedOutWithinSeconds = 5.0;

/// A child stopped by its timeout: ended TimedOut by `signal`, long before its own 30 s.
void expect_timed_out(const ChildResult& r, int signal) {
  EXPECT_EQ(r.end, ChildEnd::TimedOut);
  EXPECT_EQ(r.signal, signal);
  EXPECT_LT(r.seconds, kTimedOutWithinSeconds);
}

TEST(ChildProcess, ReportsTheExitStatusAndTheEndOfStandardError) {
  const ChildResult r = sh("echo out; echo 'error: bad mesh' >&2; exit 3");
  EXPECT_EQ(r.end, ChildEnd::Exited);
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_EQ(r.signal, 0);
  EXPECT_EQ(r.stderr_text, "error: bad mesh\n");  // stdout goes to /dev/null
  EXPECT_GT(r.pid, 0);
  EXPECT_GE(r.seconds, 0.0);
}

TEST(ChildProcess, KeepsOnlyTheEndOfALongStandardError) {
  ChildLimits limits;
  limits.stderr_bytes = 100;
  // 200 000 bytes of 'x' then a last line: the last 100 bytes stay.
  const ChildResult r = sh("head -c 200000 /dev/zero | tr '\\0' x >&2; echo END >&2", limits);
  ASSERT_EQ(r.end, ChildEnd::Exited);
  ASSERT_EQ(r.stderr_text.size(), 100u);
  EXPECT_EQ(r.stderr_text.substr(96), "END\n");
}

TEST(ChildProcess, ASignalIsReportedAsSuch) {
  const ChildResult r = sh("kill -SEGV $$");
  EXPECT_EQ(r.end, ChildEnd::Signaled);
  EXPECT_EQ(r.signal, SIGSEGV);
  EXPECT_EQ(signal_name(r.signal), "SIGSEGV");
}

TEST(ChildProcess, ATimeoutStopsTheChildAndItsProcessGroup) {
  const ChildLimits limits = timeout_limits(0.3, 0.5);
  // A grandchild in the same group must go too, or the pipe would stay open.
  const ChildResult r = sh("sleep 30 & sleep 30", limits);
  expect_timed_out(r, SIGTERM);
}

TEST(ChildProcess, ATimeoutEscalatesToSigkillWhenTermIsIgnored) {
  const ChildLimits limits = timeout_limits(0.2, 0.3);
  const ChildResult r = sh("trap '' TERM; while :; do sleep 0.05; done", limits);
  expect_timed_out(r, SIGKILL);
}

TEST(ChildProcess, SetsAndRemovesEnvironmentVariables) {
  ::setenv("RICCI_CHILD_TEST_REMOVED", "here", 1);
  const ChildResult r =
      sh("echo \"[$RICCI_CHILD_TEST_SET][${RICCI_CHILD_TEST_REMOVED-unset}]\" >&2", {},
         {"RICCI_CHILD_TEST_SET=42", "RICCI_CHILD_TEST_REMOVED"});
  ::unsetenv("RICCI_CHILD_TEST_REMOVED");
  EXPECT_EQ(r.stderr_text, "[42][unset]\n");
}

TEST(ChildProcess, AProgramThatCannotRunIsASpawnFailure) {
  const ChildResult r = run_child({"/nonexistent/ricci", "param"}, {}, {});
  EXPECT_EQ(r.end, ChildEnd::SpawnFailed);
  EXPECT_NE(r.spawn_error.find("execve failed for /nonexistent/ricci"), std::string::npos)
      << r.spawn_error;
}

TEST(ChildProcess, RefusesBadArguments) {
  EXPECT_THROW(run_child({}, {}, {}), InvalidInput);
  ChildLimits limits;
  limits.timeout_seconds = -1;
  EXPECT_THROW(run_child({"/bin/true"}, {}, limits), InvalidInput);
}

}  // namespace
}  // namespace ricci
