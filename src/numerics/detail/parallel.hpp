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
#include <future>
#include <limits>
#include <system_error>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

namespace ricci::parallel {

/// Threads by default when RICCI_NUM_THREADS is not set: the loops here are memory bound, and
/// more threads than this rarely help.
constexpr int kDefaultMaxThreads = 8;

/// Elements per thread below which a loop stays on the calling thread (starting a thread costs
/// tens of microseconds; a light per-element kernel takes a few nanoseconds).
constexpr int kDefaultMinChunk = 32768;

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
/// chunk 0 on the calling thread and the others on threads of their own (on the calling thread
/// too when no thread can be started), and returns once all are done. An exception thrown by a
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
  std::vector<std::thread> workers;
  workers.reserve(static_cast<std::size_t>(chunks - 1));
  int inline_from = chunks;  // chunks that found no thread run here, after chunk 0
  for (int c = 1; c < chunks; ++c) {
    try {
      workers.emplace_back(run, c);
    } catch (const std::system_error&) {
      inline_from = c;
      break;
    }
  }
  run(0);
  for (int c = inline_from; c < chunks; ++c) run(c);
  for (std::thread& w : workers) w.join();
  for (const std::exception_ptr& e : errors) {
    if (e) std::rethrow_exception(e);
  }
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

/// Runs `work` beside the calling thread; get() on the returned future waits for it and
/// rethrows what it threw. With one thread (RICCI_NUM_THREADS=1, or no thread to be had) it runs
/// on the calling thread at get() instead. The future's destructor waits for the work.
template <class Work>
auto run_beside(Work&& work) -> std::future<std::invoke_result_t<std::decay_t<Work>>> {
  std::decay_t<Work> task(std::forward<Work>(work));
  if (max_threads() > 1) {
    try {
      return std::async(std::launch::async, task);
    } catch (const std::system_error&) {
      // no thread: run it deferred below
    }
  }
  return std::async(std::launch::deferred, std::move(task));
}

}  // namespace ricci::parallel
