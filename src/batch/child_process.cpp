#include "ricci/batch/child_process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <map>

#include "ricci/errors.hpp"
#include "ricci/numerics/timer.hpp"

extern char** environ;

namespace ricci {

namespace {

double since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// The child's environment: ours with the overrides applied ("NAME=value" sets, "NAME" removes).
std::vector<std::string> child_environment(const std::vector<std::string>& overrides) {
  std::map<std::string, std::string> variables;
  for (char** e = environ; e != nullptr && *e != nullptr; ++e) {
    const std::string entry(*e);
    const std::size_t equals = entry.find('=');
    if (equals == std::string::npos) continue;
    variables[entry.substr(0, equals)] = entry.substr(equals + 1);
  }
  for (const std::string& o : overrides) {
    const std::size_t equals = o.find('=');
    if (equals == std::string::npos) {
      variables.erase(o);
    } else {
      variables[o.substr(0, equals)] = o.substr(equals + 1);
    }
  }
  std::vector<std::string> result;
  result.reserve(variables.size());
  for (const auto& [name, value] : variables) result.push_back(name + "=" + value);
  return result;
}

std::vector<char*> pointers(std::vector<std::string>& strings) {
  std::vector<char*> p;
  p.reserve(strings.size() + 1);
  for (std::string& s : strings) p.push_back(s.data());
  p.push_back(nullptr);
  return p;
}

/// In the child between fork and exec: async-signal-safe calls only. Reports a failure through
/// `report` (errno and a step number) and exits 127.
[[noreturn]] void exec_child(char* const* argv, char* const* envp, int stderr_fd, int report,
                             pid_t parent, double memory_limit_mb) {
  int step = 0;
  auto fail = [&]() {
    const int values[2] = {step, errno};
    [[maybe_unused]] const ssize_t n = ::write(report, values, sizeof values);
    ::_exit(127);
  };
  ::setpgid(0, 0);
  step = 1;
  // Dies with the thread that started it: a killed batch leaves no orphans. SIGTERM lets
  // `ricci` remove its temporary files first.
  if (::prctl(PR_SET_PDEATHSIG, SIGTERM) != 0) fail();
  if (::getppid() != parent) ::_exit(127);  // the parent died before prctl
  step = 2;
  sigset_t none;
  sigemptyset(&none);
  ::sigprocmask(SIG_SETMASK, &none, nullptr);
  for (const int s : {SIGPIPE, SIGINT, SIGTERM, SIGHUP, SIGQUIT}) ::signal(s, SIG_DFL);
  step = 3;
  const int null_fd = ::open("/dev/null", O_RDWR);
  if (null_fd < 0) fail();
  if (::dup2(null_fd, 0) < 0 || ::dup2(null_fd, 1) < 0 || ::dup2(stderr_fd, 2) < 0) fail();
  step = 4;
  if (memory_limit_mb > 0) {
    const auto bytes = static_cast<rlim_t>(memory_limit_mb * 1024.0 * 1024.0);
    const struct rlimit limit = {bytes, bytes};
    if (::setrlimit(RLIMIT_AS, &limit) != 0) fail();
  }
  step = 5;
  ::execve(argv[0], argv, envp);
  fail();
  ::_exit(127);  // not reached: fail() exits
}

const char* step_name(int step) {
  switch (step) {
    case 1:
      return "prctl(PR_SET_PDEATHSIG)";
    case 2:
      return "signal set-up";
    case 3:
      return "redirecting standard streams";
    case 4:
      return "setrlimit(RLIMIT_AS)";
    default:
      return "execve";
  }
}

}  // namespace

std::string signal_name(int signal) {
  switch (signal) {
    case SIGSEGV:
      return "SIGSEGV";
    case SIGABRT:
      return "SIGABRT";
    case SIGKILL:
      return "SIGKILL";
    case SIGTERM:
      return "SIGTERM";
    case SIGINT:
      return "SIGINT";
    case SIGBUS:
      return "SIGBUS";
    case SIGFPE:
      return "SIGFPE";
    case SIGILL:
      return "SIGILL";
    case SIGHUP:
      return "SIGHUP";
    case SIGPIPE:
      return "SIGPIPE";
    case SIGXCPU:
      return "SIGXCPU";
    default:
      return "signal " + std::to_string(signal);
  }
}

ChildResult run_child(const std::vector<std::string>& argv,
                      const std::vector<std::string>& env_overrides, const ChildLimits& limits) {
  if (argv.empty()) throw InvalidInput("run_child: no program given");
  if (limits.timeout_seconds < 0 || limits.memory_limit_mb < 0 || limits.kill_grace_seconds < 0 ||
      limits.stderr_bytes < 0) {
    throw InvalidInput("run_child: ChildLimits fields must be >= 0");
  }
  std::vector<std::string> arguments = argv;
  std::vector<std::string> environment = child_environment(env_overrides);
  const std::vector<char*> argp = pointers(arguments);
  const std::vector<char*> envp = pointers(environment);

  ChildResult result;
  int err_pipe[2];
  int report_pipe[2];
  if (::pipe2(err_pipe, O_CLOEXEC) != 0) {
    result.spawn_error = std::string("pipe: ") + std::strerror(errno);
    return result;
  }
  if (::pipe2(report_pipe, O_CLOEXEC) != 0) {
    result.spawn_error = std::string("pipe: ") + std::strerror(errno);
    ::close(err_pipe[0]);
    ::close(err_pipe[1]);
    return result;
  }
  const pid_t parent = ::getpid();
  const Clock::time_point start = Clock::now();
  const pid_t pid = ::fork();
  if (pid == 0) {
    exec_child(argp.data(), envp.data(), err_pipe[1], report_pipe[1], parent,
               limits.memory_limit_mb);
  }
  ::close(err_pipe[1]);
  ::close(report_pipe[1]);
  if (pid < 0) {
    result.spawn_error = std::string("fork: ") + std::strerror(errno);
    ::close(err_pipe[0]);
    ::close(report_pipe[0]);
    return result;
  }
  result.pid = pid;
  ::setpgid(pid, pid);  // also here: no race with a kill of the group before the child's own call

  // exec succeeded when the report pipe closes without data (it is close-on-exec).
  int failure[2] = {0, 0};
  ssize_t got = 0;
  do {
    got = ::read(report_pipe[0], failure, sizeof failure);
  } while (got < 0 && errno == EINTR);
  ::close(report_pipe[0]);

  bool stderr_open = true;
  bool term_sent = false, kill_sent = false;
  Clock::time_point term_time;
  std::string tail;
  int status = 0;
  struct rusage usage {};
  for (;;) {
    const pid_t waited = ::wait4(pid, &status, WNOHANG, &usage);
    if (waited == pid) break;
    if (waited < 0 && errno != EINTR) {
      result.spawn_error = std::string("wait4: ") + std::strerror(errno);
      break;
    }
    if (limits.timeout_seconds > 0 && !term_sent && since(start) > limits.timeout_seconds) {
      ::kill(-pid, SIGTERM);
      term_sent = true;
      term_time = Clock::now();
    }
    if (term_sent && !kill_sent && since(term_time) > limits.kill_grace_seconds) {
      ::kill(-pid, SIGKILL);
      kill_sent = true;
    }
    if (stderr_open) {
      struct pollfd p = {err_pipe[0], POLLIN, 0};
      const int ready = ::poll(&p, 1, 20);
      if (ready > 0) {
        char buffer[4096];
        const ssize_t n = ::read(err_pipe[0], buffer, sizeof buffer);
        if (n > 0) {
          tail.append(buffer, static_cast<std::size_t>(n));
          const auto keep = static_cast<std::size_t>(limits.stderr_bytes);
          if (tail.size() > 2 * keep + 4096) tail.erase(0, tail.size() - keep);
        } else if (n == 0 || (errno != EINTR && errno != EAGAIN)) {
          stderr_open = false;
        }
      }
    } else {
      ::usleep(5000);
    }
  }
  // What the child wrote just before it exited.
  if (stderr_open) {
    ::fcntl(err_pipe[0], F_SETFL, O_NONBLOCK);
    char buffer[4096];
    ssize_t n;
    while ((n = ::read(err_pipe[0], buffer, sizeof buffer)) > 0) {
      tail.append(buffer, static_cast<std::size_t>(n));
    }
  }
  ::close(err_pipe[0]);
  const auto keep = static_cast<std::size_t>(limits.stderr_bytes);
  if (tail.size() > keep) tail.erase(0, tail.size() - keep);
  result.stderr_text = tail;
  result.seconds = since(start);
  result.peak_memory_kb = usage.ru_maxrss;
  if (got == static_cast<ssize_t>(sizeof failure)) {
    result.end = ChildEnd::SpawnFailed;
    result.spawn_error = std::string(step_name(failure[0])) + " failed for " + argv[0] + ": " +
                         std::strerror(failure[1]);
    return result;
  }
  if (!result.spawn_error.empty()) return result;
  if (term_sent) {
    result.end = ChildEnd::TimedOut;
    result.signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
    result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  } else if (WIFSIGNALED(status)) {
    result.end = ChildEnd::Signaled;
    result.signal = WTERMSIG(status);
  } else {
    result.end = ChildEnd::Exited;
    result.exit_code = WEXITSTATUS(status);
  }
  return result;
}

}  // namespace ricci
