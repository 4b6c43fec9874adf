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
  std::vector<std::string> inputs;        // positional: the image to spectralize
  std::string to_rgb;                     // --to-rgb IN.exr: a spectral EXR to RGB
  std::vector<std::string> plot_pixels;   // --plot-pixel X,Y (repeatable): plot IN.exr's pixel
  std::string output;                     // -o OUTPUT.exr
  std::string colorspace;                 // --colorspace NAME (empty: default / detected)
  std::string mode;                       // --mode (empty: emission for --color, auto for images)
  std::string wavelengths = "380:780:5";  // --wavelengths START:END:STEP
  std::string observer = "cie1931";       // --observer
  std::string illuminant = "D65";         // --illuminant
  std::string filter;                     // --filter K (empty: the default)
  std::string model = "paper";            // --model paper|smooth
  std::string emission_basis = "flat";    // --emission-basis flat|<illuminant>
  std::string format;                     // --format: csv|json (--color), half|float (images)
  std::string compression = "zip";        // --compression
  std::string tile;                       // --tile N (empty: scanlines)
  std::string method = "table";           // --method table|exact
  std::string cache;                      // --cache DIR
  std::string threads;                    // --threads N (empty: all cores)
  std::string report;                     // --report FILE.json
  std::string config;                     // --config FILE
  int verbosity = 1;                      // -q: 0, default 1, -v: 2
};

/// A command-line mistake: printed as "spectralize ERROR: ..." with exit status 2.
struct UsageError {
  std::string message;
};

/// Runs `spectralize --color ...`: prints spectra to stdout, warnings to stderr. Returns the exit
/// status; throws UsageError for malformed values. Cost: one exact solve per colour.
int run_color(const Options& options);

/// Runs `spectralize --to-rgb IN.exr -o OUT.exr ...`: a spectral OpenEXR (any writer's) back to
/// RGB(A). Returns the exit status; throws UsageError / Error. Cost: O(pixels x bands).
int run_to_rgb(const Options& options);

/// Runs `spectralize INPUT -o OUTPUT.exr ...`: the image job, its console summary, progress and
/// --report. Returns the exit status; throws UsageError for malformed values and Error when the
/// job fails. Cost: O(pixels x bands).
int run_image(const Options& options);

/// Runs `spectralize --color R,G,B ... -o PLOT.png|.svg`: the spectra drawn as a plot (see
/// io/spectrum_plot.h). Returns the exit status; throws UsageError / Error. Cost: one exact
/// solve per colour plus the drawing, ~0.2 s.
int run_plot_color(const Options& options);

/// Runs `spectralize --plot-pixel X,Y IN.exr -o PLOT.png|.svg`: the spectrum of a pixel of any
/// spectral EXR. Returns the exit status; throws UsageError / Error. Cost: reading one row per
/// pixel plus the drawing.
int run_plot_pixel(const Options& options);

}  // namespace spectralize::tool
