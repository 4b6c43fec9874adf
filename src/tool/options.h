#pragma once
// The command line of spectralize, parsed: which command, its inputs and outputs, and the
// settings (validated by the schema, settings/settings.h). Each mistake is a UsageError (exit 2).

#include <set>
#include <string>
#include <vector>

#include "settings/settings.h"

namespace spectralize::tool {

/// Exit statuses: success, the job failed (I/O, invalid colour), the command line is wrong.
enum ExitCode : int { kExitOk = 0, kExitFailure = 1, kExitUsage = 2 };

struct Options {
  Command command = kImage;
  Settings settings;
  std::vector<std::string> colors;       // --color R,G,B (repeatable)
  std::vector<std::string> inputs;       // positional: the image to spectralize
  std::string to_rgb;                    // --to-rgb IN.exr
  std::vector<std::string> plot_pixels;  // --plot-pixel X,Y (repeatable)
  std::string output;                    // -o
  std::string report;                    // --report FILE.json
  int verbosity = 1;                     // -q: 0, default 1, -v: 2
  // ingest
  std::string inputs_from;      // --inputs-from FILE
  std::string manifest;         // --manifest FILE
  std::string shard;            // --shard I/N
  bool force = false;           // --force
  bool merge = false;           // --merge
  std::set<std::string> given;  // every flag given, for applicability checks
};

/// A command-line mistake: printed as "spectralize ERROR: ..." with exit status 2.
struct UsageError {
  std::string message;
};

/// Runs `spectralize --color ...`: prints spectra (CSV or JSON) to stdout or to -o FILE.
/// Returns the exit status; throws UsageError / Error. Cost: one exact solve per colour.
int run_color(const Options& options);

/// Runs `spectralize --to-rgb IN.exr -o OUT.exr ...`: a spectral OpenEXR (any writer's) back to
/// RGB(A). Returns the exit status; throws UsageError / Error. Cost: O(pixels x bands).
int run_to_rgb(const Options& options);

/// Runs `spectralize INPUT -o OUTPUT.exr ...`: the image job, its console summary, progress and
/// --report. Returns the exit status; throws UsageError / Error. Cost: O(pixels x bands).
int run_image(const Options& options);

/// Runs `spectralize --color R,G,B ... -o PLOT.png|.svg`: the spectra drawn as a plot (see
/// plot/spectrum_plot.h). Returns the exit status; throws UsageError / Error. Cost: one exact
/// solve per colour plus the drawing, ~0.2 s.
int run_plot_color(const Options& options);

/// Runs `spectralize ingest SRC... -o DESTDIR` (or `--merge`): a library to spectral OpenEXR,
/// its manifest and summary. Returns 0 when no file failed, 1 otherwise; throws UsageError.
/// Cost: the conversions.
int run_ingest_command(const Options& options);

/// Runs `spectralize table -o NAME.spztab`: the render-time table of a colour space. Returns
/// the exit status; throws UsageError / Error. Cost: building the table, a few seconds.
int run_table(const Options& options);

/// Runs `spectralize --plot-pixel X,Y IN.exr -o PLOT.png|.svg`: the spectrum of a pixel of any
/// spectral EXR. Returns the exit status; throws UsageError / Error. Cost: reading the rows of
/// the pixels plus the drawing.
int run_plot_pixel(const Options& options);

}  // namespace spectralize::tool
