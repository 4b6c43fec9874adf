#pragma once
// The cores of a batch, shared by the files converting at the moment (docs/DESIGN.md §12):
// each conversion uses total / running threads, asked again for every strip, so the cores of
// a file that finished (or was up to date) go to the files still converting.

#include <algorithm>
#include <atomic>

namespace spectralize {

class ThreadShare {
 public:
  /// A share of `total` threads (at least 1). Cost: O(1).
  explicit ThreadShare(int total) : total_(std::max(1, total)) {}

  /// Counts one conversion as running while it lives.
  class Running {
   public:
    explicit Running(ThreadShare& share) : share_(share) { ++share_.running_; }
    ~Running() { --share_.running_; }
    Running(const Running&) = delete;
    Running& operator=(const Running&) = delete;

   private:
    ThreadShare& share_;
  };

  /// Threads for one running conversion now: total / running, at least 1. Thread-safe. Cost: O(1).
  int now() const { return std::max(1, total_ / std::max(1, running_.load())); }
  /// All the batch's threads. Cost: O(1).
  int total() const { return total_; }

 private:
  int total_;
  std::atomic<int> running_{0};
};

}  // namespace spectralize
