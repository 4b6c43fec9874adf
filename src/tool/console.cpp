#include "tool/console.h"

#include <fmt/core.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <memory>

namespace spectralize::tool {

LogFn console_log(int verbosity) {
  return [verbosity](int level, const std::string& message) {
    if (level == 0 && verbosity > 0)
      fmt::print(stderr, "spectralize WARNING: {}\n", message);
    else if (level > 0 && verbosity >= 2)
      fmt::print(stderr, "spectralize: {}\n", message);
  };
}

ProgressFn console_progress(int verbosity, const std::string& what) {
  using Clock = std::chrono::steady_clock;
  if (verbosity == 0) return nullptr;
  struct State {
    Clock::time_point start = Clock::now(), last = Clock::now();
    bool tty = ::isatty(STDERR_FILENO) != 0;
    bool verbose = false;
    int tenth = 0;
  };
  auto state = std::make_shared<State>();
  state->verbose = verbosity >= 2;
  return [state, what](std::uint64_t done, std::uint64_t total) {
    if (total == 0) return;
    const auto now = Clock::now();
    const double t = std::chrono::duration<double>(now - state->start).count();
    const double f = static_cast<double>(done) / static_cast<double>(total);
    const double rate = t > 0 ? static_cast<double>(done) / t / 1e6 : 0;
    const double eta = f > 0 ? t * (1 - f) / f : 0;
    if (state->tty) {
      const int filled = static_cast<int>(f * 30);
      fmt::print(stderr, "\r[{:<30}] {:3.0f}%  {:.2f} Mpixel/s  ETA {:.0f} s ",
                 std::string(filled, '#'), 100 * f, rate, eta);
      if (done == total) fmt::print(stderr, "\n");
      std::fflush(stderr);
      return;
    }
    // Off a terminal (farm logs): a line every 10 seconds, and with -v also every 10%.
    const int tenth = static_cast<int>(f * 10);
    const bool due = std::chrono::duration<double>(now - state->last).count() >= 10 ||
                     (state->verbose && tenth > state->tenth);
    if (due && done < total) {
      state->last = now;
      state->tenth = tenth;
      fmt::print(stderr, "spectralize: {}: {:.0f}% ({:.2f} Mpixel/s, ETA {:.0f} s)\n", what,
                 100 * f, rate, eta);
    }
  };
}

void check_stdout() {
  errno = 0;
  if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
    const int err = errno;
    throw Error(std::string("cannot write to standard output: ") +
                (err ? std::strerror(err) : "write error"));
  }
}

}  // namespace spectralize::tool
