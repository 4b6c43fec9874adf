#pragma once
// What every command says on the console and how its errors are sorted: a mistake in a
// command-line value (exit 2, naming the flag) or a failure of the job (exit 1); the log and
// progress at each verbosity; standard output checked to the last byte.

#include <string>
#include <string_view>

#include "pipeline/job_log.h"
#include "spectralize/core/error.h"
#include "tool/options.h"

namespace spectralize::tool {

/// Runs `fn`, turning a mistake in a command-line value (an Error) into a UsageError (exit 2),
/// prefixed "<flag>: " when a flag is given; a FileError (a file that cannot be read or written)
/// and a ConfigError (the OCIO config's own fault, or a config that does not load) are job
/// failures (exit 1) and pass unchanged. The one place that decides which errors are the
/// command line's: main() maps UsageError to 2 and every other error to 1. Cost: that of fn.
template <typename Fn>
auto usage_checked(std::string_view flag, Fn&& fn) {
  try {
    return fn();
  } catch (const ConfigError&) {
    throw;
  } catch (const FileError&) {
    throw;
  } catch (const Error& e) {
    throw UsageError{flag.empty() ? std::string(e.what()) : std::string(flag) + ": " + e.what()};
  }
}

/// Warnings unless -q; stage details (levels 1 and 2) with -v. Cost: O(1).
LogFn console_log(int verbosity);

/// A progress display on stderr: a bar when stderr is a terminal, a line every few seconds
/// otherwise (farm logs) when verbose. Cost: O(1) per call.
ProgressFn console_progress(int verbosity, const std::string& what);

/// Flushes stdout and throws Error when anything written to it was lost (a full disk, a closed
/// pipe). Cost: a flush.
void check_stdout();

}  // namespace spectralize::tool
