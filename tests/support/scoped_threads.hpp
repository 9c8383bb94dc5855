#pragma once
/// \file
/// Sets the thread count the parallel loops read (RICCI_NUM_THREADS) for a scope, and puts the
/// variable back as it was (set or unset) when the scope ends: tests that compare 1, 2 and 3
/// threads.

#include <cstdlib>
#include <optional>
#include <string>

namespace ricci::testing {

class ScopedThreads {
 public:
  explicit ScopedThreads(const char* threads) {
    if (const char* before = std::getenv("RICCI_NUM_THREADS")) saved_ = before;
    setenv("RICCI_NUM_THREADS", threads, 1);
  }
  ~ScopedThreads() {
    if (saved_) {
      setenv("RICCI_NUM_THREADS", saved_->c_str(), 1);
    } else {
      unsetenv("RICCI_NUM_THREADS");
    }
  }
  ScopedThreads(const ScopedThreads&) = delete;
  ScopedThreads& operator=(const ScopedThreads&) = delete;

 private:
  std::optional<std::string> saved_;
};

}  // namespace ricci::testing
