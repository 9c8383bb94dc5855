#include "numerics/detail/parallel.hpp"

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <numeric>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "numerics/detail/helper_threads.hpp"

namespace ricci {
namespace {

/// RICCI_NUM_THREADS set for the scope (the loops read it at every call).
class ThreadCount {
 public:
  explicit ThreadCount(int n) {
    if (const char* v = std::getenv("RICCI_NUM_THREADS")) saved_ = v;
    setenv("RICCI_NUM_THREADS", std::to_string(n).c_str(), 1);
  }
  ~ThreadCount() {
    if (saved_.empty()) {
      unsetenv("RICCI_NUM_THREADS");
    } else {
      setenv("RICCI_NUM_THREADS", saved_.c_str(), 1);
    }
  }
  ThreadCount(const ThreadCount&) = delete;
  ThreadCount& operator=(const ThreadCount&) = delete;

 private:
  std::string saved_;
};

/// Every element visited exactly once, by chunks that cover the range in order.
void expect_each_once(std::int64_t n, int chunks) {
  std::vector<std::atomic<int>> visits(static_cast<std::size_t>(n));
  std::vector<std::int64_t> begins(static_cast<std::size_t>(chunks), -1);
  parallel::run_chunks(n, chunks, [&](std::int64_t begin, std::int64_t end, int c) {
    begins[static_cast<std::size_t>(c)] = begin;
    for (std::int64_t i = begin; i < end; ++i) visits[static_cast<std::size_t>(i)]++;
  });
  for (std::int64_t i = 0; i < n; ++i) ASSERT_EQ(visits[static_cast<std::size_t>(i)], 1) << i;
  for (int c = 0; c < chunks; ++c) EXPECT_EQ(begins[static_cast<std::size_t>(c)], n * c / chunks);
}

TEST(Parallel, RunChunksVisitsEveryElementOnce) {
  for (int threads : {1, 2, 4, 9}) {
    const ThreadCount count(threads);
    for (int chunks : {1, 2, 3, 8, 17}) {
      for (std::int64_t n : {1, 5, 1000, 100000}) expect_each_once(n, chunks);
    }
  }
}

TEST(Parallel, ReductionsDoNotDependOnTheThreadCount) {
  const std::int64_t n = 200000;
  auto value = [](std::int64_t i) { return static_cast<double>((i * 7919) % 1000003); };
  std::int64_t count1 = 0, first1 = 0;
  double max1 = 0;
  {
    const ThreadCount one(1);
    count1 = parallel::count_if(
        n, [&](std::int64_t i) { return value(i) > 5e5; }, 1000);
    first1 = parallel::first_failing(
        n, [&](std::int64_t i) { return value(i) < 9.9e5; }, 1000);
    max1 = parallel::max_of(n, value, 0.0, 1000);
  }
  for (int threads : {2, 3, 8}) {
    const ThreadCount count(threads);
    EXPECT_EQ(parallel::count_if(
                  n, [&](std::int64_t i) { return value(i) > 5e5; }, 1000),
              count1);
    EXPECT_EQ(parallel::first_failing(
                  n, [&](std::int64_t i) { return value(i) < 9.9e5; }, 1000),
              first1);
    EXPECT_EQ(parallel::max_of(n, value, 0.0, 1000), max1);
  }
}

TEST(Parallel, AnExceptionOfTheLowestChunkIsRethrown) {
  const ThreadCount count(4);
  for (int round = 0; round < 50; ++round) {
    try {
      parallel::run_chunks(1000, 4, [](std::int64_t, std::int64_t, int c) {
        if (c >= 1) throw std::runtime_error("chunk " + std::to_string(c));
      });
      FAIL() << "nothing thrown";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "chunk 1");
    }
  }
}

TEST(Parallel, NestedLoopsAndLoopsFromSeveralThreadsFinish) {
  // Loops inside chunks and loops started from tasks beside: helpers are claimed by whoever
  // asks first, the rest run on threads of their own or inline.
  const ThreadCount count(4);
  std::atomic<std::int64_t> total{0};
  auto nested = [&] {
    parallel::for_chunks(
        64,
        [&](std::int64_t begin, std::int64_t end, int) {
          for (std::int64_t i = begin; i < end; ++i) {
            std::int64_t local = 0;
            parallel::for_each(
                100, [&](std::int64_t) {}, 10);
            local += 1;
            total += local;
          }
        },
        4);
  };
  auto beside = parallel::run_beside(nested);
  nested();
  beside.get();
  EXPECT_EQ(total.load(), 128);
}

TEST(Parallel, RunBesideReturnsRethrowsAndWaits) {
  for (int threads : {1, 2}) {
    const ThreadCount count(threads);
    EXPECT_EQ(parallel::run_beside([] { return 42; }).get(), 42);
    auto failing = parallel::run_beside([]() -> int { throw std::runtime_error("beside"); });
    EXPECT_THROW(failing.get(), std::runtime_error);
    // A task dropped unwaited is either never started or waited for: never left running.
    std::atomic<int> state{0};
    {
      auto dropped = parallel::run_beside([&] {
        state = 1;
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
        state = 2;
      });
    }
    EXPECT_NE(state.load(), 1);
    parallel::Task<void> chained;
    chained = parallel::run_beside([&] { state = 3; });
    chained.wait();
    EXPECT_EQ(state.load(), 3);
    EXPECT_EQ(parallel::Task<std::string>::ready("done").get(), "done");
  }
}

// With every helper busy, a task beside starts no thread of its own (it would share a busy core):
// it runs on the calling thread at get(), and a dropped one never runs.
TEST(Parallel, TaskBesideBusyHelpersRunsOnTheCallerAtGet) {
  const int helpers = parallel::helper_threads::capacity();
  if (helpers < 1 || parallel::max_threads() != helpers + 1) {
    GTEST_SKIP() << "needs the default thread count on 2 or more cores";
  }
  std::atomic<bool> release{false};
  std::atomic<int> busy{0};
  std::vector<parallel::Task<void>> blockers;
  blockers.reserve(static_cast<std::size_t>(helpers));
  for (int i = 0; i < helpers; ++i) {
    blockers.push_back(parallel::run_beside([&] {
      ++busy;
      while (!release) std::this_thread::yield();
    }));
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (busy < helpers && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::yield();
  }
  ASSERT_EQ(busy.load(), helpers);
  auto where = parallel::run_beside([] { return std::this_thread::get_id(); });
  std::atomic<int> ran{0};
  {
    auto dropped = parallel::run_beside([&] { ++ran; });
  }
  EXPECT_EQ(where.get(), std::this_thread::get_id());
  EXPECT_EQ(ran.load(), 0);
  release = true;
  for (auto& b : blockers) b.get();
}

TEST(HelperThreads, AJobRunsOnceWhetherAHelperOrThePosterTakesIt) {
  // Many short jobs from two posters at once, some finished at once (often taken back before a
  // helper wakes), some after a pause (taken by a helper): each runs exactly once.
  namespace helper_threads = parallel::helper_threads;
  using helper_threads::Job;
  std::atomic<int> runs{0};
  auto poster = [&](int rounds) {
    for (int r = 0; r < rounds; ++r) {
      Job job;
      job.fn = [](void* context, int) { static_cast<std::atomic<int>*>(context)->fetch_add(1); };
      job.context = &runs;
      if (helper_threads::post_job(job, 3)) {
        if (r % 3 == 0) std::this_thread::sleep_for(std::chrono::microseconds(r % 7 * 20));
        helper_threads::finish_job(job);
        EXPECT_EQ(job.done.load(), 1);
      } else {
        job.fn(job.context, 0);
      }
    }
  };
  std::thread other(poster, 3000);
  poster(3000);
  other.join();
  EXPECT_EQ(runs.load(), 6000);
}

}  // namespace
}  // namespace ricci
