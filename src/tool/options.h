#pragma once
// The command line of spectralize, parsed but not yet validated: each command checks the values
// it uses and reports the flag and value that are wrong (exit status 2).

#include <string>
#include <vector>

namespace spectralize::tool {

/// Exit statuses: success, the job failed (I/O, invalid colour), the command line is wrong.
enum ExitCode : int { kExitOk = 0, kExitFailure = 1, kExitUsage = 2 };

struct Options {
  std::vector<std::string> colors;        // --color R,G,B (repeatable)
  std::string colorspace;                 // --colorspace NAME (empty: default)
  std::string mode = "emission";          // --mode
  std::string wavelengths = "380:780:5";  // --wavelengths START:END:STEP
  std::string observer = "cie1931";       // --observer
  std::string illuminant = "D65";         // --illuminant
  std::string filter;                     // --filter K (empty: the default)
  std::string format = "csv";             // --format csv|json
  std::string config;                     // --config FILE
};

/// A command-line mistake: printed as "spectralize ERROR: ..." with exit status 2.
struct UsageError {
  std::string message;
};

/// Runs `spectralize --color ...`: prints spectra to stdout, warnings to stderr. Returns the exit
/// status; throws UsageError for malformed values. Cost: one exact solve per colour.
int run_color(const Options& options);

}  // namespace spectralize::tool
