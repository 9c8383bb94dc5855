#include "numerics/detail/helper_threads.hpp"

#include <pthread.h>

#include <algorithm>
#include <array>
#include <mutex>
#include <system_error>
#include <thread>

namespace ricci::parallel::helper_threads {

/// One helper thread: `slot` holds the job posted to it until it (or the poster) takes it;
/// `claimed` is 1 from the post until the job has run.
struct Helper {
  std::atomic<Job*> slot{nullptr};
  std::atomic<int> claimed{0};
  std::atomic<int> sleeping{0};
};

namespace {

/// At most this many helpers (parallel.hpp's kDefaultMaxThreads less the calling thread).
constexpr int kMaxHelpers = 7;

/// Polls between looks at the clock while a helper waits for work.
constexpr int kPollsPerClockRead = 64;

struct Pool {
  std::array<Helper, kMaxHelpers> helpers;
  std::atomic<int> started{0};
  std::mutex starting;
  /// Set in a child of fork(): the helpers did not come along.
  std::atomic<bool> forked{false};
  std::atomic<int> tasks_beside{0};
  /// Helpers beyond the other cores would poll on a core someone else needs.
  std::atomic<int> capacity{
      std::clamp(static_cast<int>(std::thread::hardware_concurrency()) - 1, 0, kMaxHelpers)};
};

Pool& pool() {
  // Never destroyed: detached helpers may still be polling it while the process exits.
  static Pool* const p = [] {
    auto* created = new Pool;
    pthread_atfork(nullptr, nullptr, [] { pool().forked.store(true); });
    return created;
  }();
  return *p;
}

inline void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__)
  asm volatile("yield");
#endif
}

/// The job in the helper's slot, taken (nullptr when there is none, or the poster took it back).
Job* take(Helper& h) {
  Job* job = h.slot.load(std::memory_order_acquire);
  if (job == nullptr) return nullptr;
  return h.slot.compare_exchange_strong(job, nullptr, std::memory_order_acq_rel) ? job : nullptr;
}

/// Polls for a job for kHelperSpin (not while tasks run beside: the helper would take their
/// core), then sleeps until one is posted.
Job* wait_for_job(Pool& p, Helper& h) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point until = Clock::now() + kHelperSpin;
  for (int polls = 1;; ++polls) {
    if (Job* job = take(h)) return job;
    if (polls % kPollsPerClockRead == 0 &&
        (p.tasks_beside.load(std::memory_order_relaxed) > 0 || Clock::now() >= until)) {
      break;
    }
    cpu_relax();
  }
  for (;;) {
    // (A poster stores the slot, then reads `sleeping`; this stores `sleeping`, then reads the
    // slot: in their single total order one of them sees the other, so no post goes unnoticed.)
    h.sleeping.store(1);
    if (h.slot.load() == nullptr) h.slot.wait(nullptr);
    h.sleeping.store(0);
    if (Job* job = take(h)) return job;
  }
}

void helper_loop(Helper& h) {
  Pool& p = pool();
  for (;;) {
    Job* job = wait_for_job(p, h);
    job->fn(job->context, job->index);  // (parallel.hpp's chunks catch what they throw)
    // Free before done: the poster may post again as soon as it sees done, and `job` is not
    // touched after done.
    h.claimed.store(0, std::memory_order_release);
    job->done.store(1, std::memory_order_release);
  }
}

/// Claims an idle helper (starting one when fewer than `max_helpers` run), or nullptr.
Helper* claim(Pool& p, int max_helpers) {
  const int wanted = std::min(max_helpers, p.capacity.load(std::memory_order_relaxed));
  int running = std::min(p.started.load(std::memory_order_acquire), wanted);
  for (int i = 0; i < running; ++i) {
    int idle = 0;
    if (p.helpers[i].claimed.compare_exchange_strong(idle, 1, std::memory_order_acquire)) {
      return &p.helpers[i];
    }
  }
  if (running >= wanted) return nullptr;
  const std::lock_guard<std::mutex> lock(p.starting);
  running = p.started.load(std::memory_order_relaxed);
  if (running >= wanted) return nullptr;
  Helper& h = p.helpers[running];
  h.claimed.store(1, std::memory_order_relaxed);
  try {
    std::thread(helper_loop, std::ref(h)).detach();
  } catch (const std::system_error&) {
    h.claimed.store(0, std::memory_order_relaxed);
    p.capacity.store(running, std::memory_order_relaxed);  // (no further helper is tried)
    return nullptr;
  }
  p.started.store(running + 1, std::memory_order_release);
  return &h;
}

/// Waits for a job a helper has taken (a chunk: microseconds; a task beside: as long as it runs,
/// so the wait soon yields the core).
void wait_until_done(const Job& job) {
  for (int polls = 1; job.done.load(std::memory_order_acquire) == 0; ++polls) {
    if (polls % kPollsPerClockRead == 0) {
      std::this_thread::yield();
    } else {
      cpu_relax();
    }
  }
}

/// Takes a posted job back from its helper's slot, which then is free again: true when the
/// helper had not taken it (it will never run it).
bool take_back(Job& job) {
  Helper& h = *job.helper;
  Job* mine = &job;
  if (!h.slot.compare_exchange_strong(mine, nullptr, std::memory_order_acq_rel)) return false;
  h.claimed.store(0, std::memory_order_release);
  return true;
}

}  // namespace

bool post_job(Job& job, int max_helpers) {
  Pool& p = pool();
  if (max_helpers <= 0 || p.forked.load(std::memory_order_relaxed)) return false;
  Helper* h = claim(p, max_helpers);
  if (h == nullptr) return false;
  job.helper = h;
  job.done.store(0, std::memory_order_relaxed);
  h->slot.store(&job);
  if (h->sleeping.load() != 0) h->slot.notify_one();
  return true;
}

int capacity() {
  return pool().capacity.load(std::memory_order_relaxed);
}

void finish_job(Job& job) {
  if (take_back(job)) {
    // Not taken yet (the helper sleeps or is still finishing something): run it here.
    job.fn(job.context, job.index);
    job.done.store(1, std::memory_order_release);
    return;
  }
  wait_until_done(job);
}

void withdraw_job(Job& job) {
  if (!take_back(job)) wait_until_done(job);
}

void task_beside_started() {
  pool().tasks_beside.fetch_add(1, std::memory_order_relaxed);
}

void task_beside_finished() {
  pool().tasks_beside.fetch_sub(1, std::memory_order_relaxed);
}

}  // namespace ricci::parallel::helper_threads
