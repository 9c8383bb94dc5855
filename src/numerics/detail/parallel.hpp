#pragma once
/// \file
/// Internal: fork-join loops over index ranges (faces, edges, vertices) and tasks run beside the
/// calling thread, for the kernels of every module.
///
/// Results never depend on the number of threads. A loop body writes only the elements of its
/// own range (plus values private to its chunk), and the reductions offered here are exact:
/// integer counts, maxima, minima and first indices, whose value is the same however the range
/// is split. Floating-point sums stay sequential (their rounding depends on the order).
///
/// The number of threads is RICCI_NUM_THREADS when that is set to a positive integer, else the
/// hardware's concurrency, at most kDefaultMaxThreads. It is read at every call, so a process may
/// change it between calls (tests compare 1 and several threads this way).
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <system_error>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

#include "numerics/detail/helper_threads.hpp"

namespace ricci::parallel {

/// Threads by default when RICCI_NUM_THREADS is not set: the loops here are memory bound, and
/// more threads than this rarely help.
constexpr int kDefaultMaxThreads = 8;

/// Elements per thread below which a loop stays on the calling thread. A light per-element
/// kernel takes a few nanoseconds, and a helper thread at hand (helper_threads.hpp) takes a
/// chunk within a microsecond or two; a loop whose chunks found no helper waits for no sleeping
/// one (it runs them itself). 32768 when every chunk started a thread of its own (40-50 us).
constexpr int kDefaultMinChunk = 4096;

/// Threads loops and tasks may use (>= 1).
inline int max_threads() {
  if (const char* text = std::getenv("RICCI_NUM_THREADS")) {
    char* end = nullptr;
    const long n = std::strtol(text, &end, 10);
    if (end != text && *end == '\0' && n >= 1) return static_cast<int>(std::min(n, 1024L));
  }
  static const int hardware = static_cast<int>(std::thread::hardware_concurrency());
  return std::clamp(hardware, 1, kDefaultMaxThreads);
}

/// Chunks a loop over n elements is split into: at most max_threads() and n / min_chunk, at
/// least 1.
inline int num_chunks(std::int64_t n, std::int64_t min_chunk = kDefaultMinChunk) {
  const std::int64_t by_size = n / std::max<std::int64_t>(min_chunk, 1);
  return static_cast<int>(std::clamp<std::int64_t>(by_size, 1, max_threads()));
}

/// Calls body(begin, end, chunk) on `chunks` consecutive chunks [begin, end) covering [0, n),
/// chunk 0 on the calling thread and the others on helper threads (helper_threads.hpp), or on
/// the calling thread when no helper is free (the other cores are busy then: a thread started
/// for the chunk would only share one); returns once all are done. An exception thrown by a
/// body is rethrown here (the lowest chunk's).
template <class Body>
void run_chunks(std::int64_t n, int chunks, Body&& body) {
  if (n <= 0) return;
  if (chunks <= 1) {
    body(std::int64_t{0}, n, 0);
    return;
  }
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(chunks));
  auto run = [&](int c) {
    try {
      body(n * c / chunks, n * (c + 1) / chunks, c);
    } catch (...) {
      errors[static_cast<std::size_t>(c)] = std::current_exception();
    }
  };
  using Run = decltype(run);
  const auto size = static_cast<std::size_t>(chunks - 1);
  std::unique_ptr<helper_threads::Job[]> jobs(new helper_threads::Job[size]);
  int posted = 0;  // chunks 1 .. posted went to helpers
  const int helpers = max_threads() - 1;
  while (posted + 1 < chunks) {
    helper_threads::Job& job = jobs[static_cast<std::size_t>(posted)];
    job.fn = [](void* context, int index) { (*static_cast<Run*>(context))(index); };
    job.context = &run;
    job.index = posted + 1;
    if (!helper_threads::post_job(job, helpers)) break;
    ++posted;
  }
  run(0);
  for (int c = posted + 1; c < chunks; ++c) run(c);
  for (int j = 0; j < posted; ++j) helper_threads::finish_job(jobs[static_cast<std::size_t>(j)]);
  for (const std::exception_ptr& e : errors) {
    if (e) std::rethrow_exception(e);
  }
}

/// Runs `first` on the calling thread and `second` beside it (on a helper when one is free, else
/// after `first`); returns once both are done, rethrowing first's exception, else second's. For
/// two pieces of work that touch disjoint data (the groups of an elimination tree's split).
template <class First, class Second>
void run_pair(First&& first, Second&& second) {
  run_chunks(2, 2, [&](std::int64_t begin, std::int64_t, int) {
    if (begin == 0) {
      first();
    } else {
      second();
    }
  });
}

/// run_chunks with num_chunks(n, min_chunk) chunks.
template <class Body>
void for_chunks(std::int64_t n, Body&& body, std::int64_t min_chunk = kDefaultMinChunk) {
  run_chunks(n, num_chunks(n, min_chunk), std::forward<Body>(body));
}

/// Calls body(i) for every i in [0, n).
template <class Body>
void for_each(std::int64_t n, Body&& body, std::int64_t min_chunk = kDefaultMinChunk) {
  for_chunks(
      n,
      [&](std::int64_t begin, std::int64_t end, int) {
        for (std::int64_t i = begin; i < end; ++i) body(i);
      },
      min_chunk);
}

/// Number of i in [0, n) with predicate(i).
template <class Predicate>
std::int64_t count_if(std::int64_t n, Predicate&& predicate,
                      std::int64_t min_chunk = kDefaultMinChunk) {
  const int chunks = num_chunks(n, min_chunk);
  std::vector<std::int64_t> counts(static_cast<std::size_t>(chunks), 0);
  run_chunks(n, chunks, [&](std::int64_t begin, std::int64_t end, int c) {
    std::int64_t count = 0;
    for (std::int64_t i = begin; i < end; ++i) count += predicate(i) ? 1 : 0;
    counts[static_cast<std::size_t>(c)] = count;
  });
  std::int64_t total = 0;
  for (const std::int64_t c : counts) total += c;
  return total;
}

/// Calls ok = body(i) for every i in [0, n) (each call runs whatever the others return) and
/// returns the smallest i whose call returned false, or -1: the same however the range is split.
template <class Body>
std::int64_t first_failing(std::int64_t n, Body&& body, std::int64_t min_chunk = kDefaultMinChunk) {
  const int chunks = num_chunks(n, min_chunk);
  std::vector<std::int64_t> first(static_cast<std::size_t>(chunks), -1);
  run_chunks(n, chunks, [&](std::int64_t begin, std::int64_t end, int c) {
    for (std::int64_t i = begin; i < end; ++i) {
      if (!body(i) && first[static_cast<std::size_t>(c)] < 0)
        first[static_cast<std::size_t>(c)] = i;
    }
  });
  for (const std::int64_t i : first) {
    if (i >= 0) return i;
  }
  return -1;
}

/// max(initial, value(i) for i in [0, n)): the maximum of doubles is exact, so any split gives
/// the same result (NaN values are skipped, as std::max(x, NaN) skips them).
template <class Value>
double max_of(std::int64_t n, Value&& value, double initial,
              std::int64_t min_chunk = kDefaultMinChunk) {
  const int chunks = num_chunks(n, min_chunk);
  std::vector<double> maxima(static_cast<std::size_t>(chunks), initial);
  run_chunks(n, chunks, [&](std::int64_t begin, std::int64_t end, int c) {
    double m = initial;
    for (std::int64_t i = begin; i < end; ++i) m = std::max(m, static_cast<double>(value(i)));
    maxima[static_cast<std::size_t>(c)] = m;
  });
  double m = initial;
  for (const double x : maxima) m = std::max(m, x);
  return m;
}

/// The result of run_beside. get() waits for the task (running it on the calling thread when no
/// helper has taken it yet: a sleeping helper never holds it up) and returns what it returned,
/// or rethrows what it threw. A task dropped before get() (destroyed, or assigned over) that no
/// thread has started is not run at all; one that has started is waited for, as std::async's
/// future waits.
template <class T>
class Task {
 public:
  Task() = default;
  /// A task done already, holding `value`.
  template <class Value>
  static Task ready(Value&& value) {
    Task task;
    task.state_ = std::make_unique<State>();
    task.state_->value.emplace(std::forward<Value>(value));
    task.state_->mode = Mode::Finished;
    return task;
  }
  Task(Task&& other) noexcept = default;
  Task& operator=(Task&& other) noexcept {
    if (this != &other) {
      drop();
      state_ = std::move(other.state_);
    }
    return *this;
  }
  Task(const Task&) = delete;
  Task& operator=(const Task&) = delete;
  ~Task() { drop(); }

  bool valid() const { return state_ != nullptr; }
  /// Waits until the task has run (running it here when no thread has taken it).
  void wait() {
    if (state_) state_->finish();
  }
  T get() {
    wait();
    const std::unique_ptr<State> done = std::move(state_);
    if (done->error) std::rethrow_exception(done->error);
    if constexpr (!std::is_void_v<T>) return std::move(*done->value);
  }

 private:
  template <class Work>
  friend Task<std::invoke_result_t<std::decay_t<Work>>> run_beside(Work&& work);

  enum class Mode { Posted, OwnThread, Deferred, Finished };
  struct State {
    std::function<T()> work;
    std::conditional_t<std::is_void_v<T>, char, std::optional<T>> value{};
    std::exception_ptr error;
    helper_threads::Job job;
    std::thread thread;
    Mode mode = Mode::Deferred;

    void run() {
      try {
        if constexpr (std::is_void_v<T>) {
          work();
        } else {
          value.emplace(work());
        }
      } catch (...) {
        error = std::current_exception();
      }
    }
    void finish() {
      switch (mode) {
        case Mode::Posted:
          helper_threads::finish_job(job);
          break;
        case Mode::OwnThread:
          thread.join();
          break;
        case Mode::Deferred:
          run();
          break;
        case Mode::Finished:
          break;
      }
      mode = Mode::Finished;
    }
  };

  void drop() {
    if (!state_) return;
    if (state_->mode == Mode::Posted) {
      helper_threads::withdraw_job(state_->job);
    } else if (state_->mode == Mode::OwnThread) {
      state_->thread.join();
    }
    state_.reset();
  }

  std::unique_ptr<State> state_;
};

/// Runs `work` beside the calling thread: on a helper thread (helper_threads.hpp) when one is
/// free; when none is, on the calling thread at get() (or, with RICCI_NUM_THREADS above the
/// helpers there can be, on a thread of its own); with one thread (RICCI_NUM_THREADS=1, or no
/// thread to be had) on the calling thread at get() too.
template <class Work>
Task<std::invoke_result_t<std::decay_t<Work>>> run_beside(Work&& work) {
  using T = std::invoke_result_t<std::decay_t<Work>>;
  using State = typename Task<T>::State;
  using Mode = typename Task<T>::Mode;
  Task<T> task;
  task.state_ = std::make_unique<State>();
  State& state = *task.state_;
  state.work = std::forward<Work>(work);
  if (max_threads() <= 1) return task;  // (Deferred)
  state.job.fn = [](void* context, int) { static_cast<State*>(context)->run(); };
  state.job.context = &state;
  if (helper_threads::post_job(state.job, max_threads() - 1)) {
    state.mode = Mode::Posted;
    return task;
  }
  // Every helper is busy. Where there are as many helpers as threads allowed beside the caller,
  // every core has work, so a thread of its own would share one and only add its start (40-50
  // us): the task runs on the calling thread at get(). (camelhead, 4 cones, started 17 threads
  // for halves of split solves while the cut ran beside the flow.) Only threads asked for beyond
  // the helpers (RICCI_NUM_THREADS above the cores) start threads of their own.
  if (helper_threads::capacity() + 1 >= max_threads()) return task;  // (Deferred)
  try {
    helper_threads::task_beside_started();
    state.thread = std::thread([&state] {
      state.run();
      helper_threads::task_beside_finished();
    });
    state.mode = Mode::OwnThread;
  } catch (const std::system_error&) {
    helper_threads::task_beside_finished();  // (Deferred: no thread to be had)
  }
  return task;
}

}  // namespace ricci::parallel
