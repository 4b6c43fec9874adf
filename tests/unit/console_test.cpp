// The console (tool/console.h): errors sorted into the command line's (exit 2, naming the flag)
// and the job's (exit 1); what is said on stderr at each verbosity.

#include "tool/console.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "test_support.h"

namespace spectralize::tool {
namespace {

TEST(Console, ValueMistakesAreTheCommandLinesAndFileOrConfigFailuresTheJobs) {
  try {
    usage_checked("--wavelengths", []() -> int { throw Error("step must be positive"); });
    ADD_FAILURE() << "no UsageError";
  } catch (const UsageError& e) {
    EXPECT_EQ(e.message, "--wavelengths: step must be positive");
  }
  try {
    usage_checked("", []() -> int { throw Error("bad value"); });
    ADD_FAILURE() << "no UsageError";
  } catch (const UsageError& e) {
    EXPECT_EQ(e.message, "bad value");
  }
  // A file or the config at fault: exit 1, the message unchanged.
  EXPECT_THROW(usage_checked("-o", []() -> int { throw FileError("'x.exr': disk full"); }),
               FileError);
  EXPECT_THROW(usage_checked("--config", []() -> int { throw ConfigError("no such file"); }),
               ConfigError);
  EXPECT_EQ(usage_checked("--x", [] { return 7; }), 7);
}

TEST(Console, TheConsoleSaysWarningsUnlessQuietAndDetailsWhenVerbose) {
  const auto said = [](int verbosity, int level) {
    testing::internal::CaptureStderr();
    console_log(verbosity)(level, "m");
    return testing::internal::GetCapturedStderr();
  };
  EXPECT_EQ(said(0, 0), "");  // -q
  EXPECT_EQ(said(1, 0), "spectralize WARNING: m\n");
  EXPECT_EQ(said(1, 1), "");
  EXPECT_EQ(said(2, 1), "spectralize: m\n");  // -v
  EXPECT_EQ(said(2, 2), "spectralize: m\n");
  EXPECT_EQ(console_progress(0, "x"), nullptr);  // -q: no progress at all
}

}  // namespace
}  // namespace spectralize::tool
