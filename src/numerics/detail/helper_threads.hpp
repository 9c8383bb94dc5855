#pragma once
/// \file
/// Internal: the helper threads behind parallel.hpp's loops. Starting a thread costs 40-50 us
/// here, and so does waking one that sleeps, so a loop split across fresh threads pays off only
/// above tens of thousands of light elements: a 3k-vertex mesh ran every loop on one core. A
/// helper that has just finished a chunk keeps polling for the next one for a short while
/// (kHelperSpin), and takes a posted chunk within a microsecond or so; the loops of one run come
/// much closer together than that, so the helpers stay at hand through a run and sleep between
/// runs.
///
/// A chunk posted to a helper that has not taken it yet is taken back by the poster
/// (finish_job): a sleeping helper never makes a loop wait for it. Which thread runs a chunk
/// never changes a result (parallel.hpp's loops are exact whatever the split).
#include <atomic>
#include <chrono>

namespace ricci::parallel::helper_threads {

/// How long a helper keeps polling for work after its last chunk before it sleeps.
constexpr std::chrono::microseconds kHelperSpin{500};

struct Helper;

/// One chunk handed to a helper: fn(context, index). `done` turns 1 once it has run (on the
/// helper, or on the poster that took it back).
struct Job {
  void (*fn)(void* context, int index) = nullptr;
  void* context = nullptr;
  int index = 0;
  Helper* helper = nullptr;  ///< where it was posted
  std::atomic<int> done{0};
};

/// Hands `job` to an idle helper (starting one when fewer than `max_helpers` exist); false when
/// none is free, in a forked child, or when no thread can be started. Each posted job must be
/// passed to finish_job before it goes out of scope.
bool post_job(Job& job, int max_helpers);

/// Helpers there may be at most: the cores beyond the calling thread's (at most 7), less where
/// a thread could not be started.
int capacity();

/// Waits until a posted job has run: runs it on the calling thread when its helper has not
/// taken it yet.
void finish_job(Job& job);

/// Drops a posted job: takes it back when its helper has not taken it yet (it then never runs),
/// else waits until it has run.
void withdraw_job(Job& job);

/// Tasks running beside the calling thread (parallel::run_beside) count themselves here while
/// they run: helpers then sleep at once instead of polling, which would take a core from them.
void task_beside_started();
void task_beside_finished();

}  // namespace ricci::parallel::helper_threads
