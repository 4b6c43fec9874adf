#pragma once
// What the commands share: turning core and io errors into usage errors that name the flag,
// the --color values, the console log and progress, and the checked report and stdout output.

#include <memory>
#include <string>
#include <vector>

#include "colour/colour_space.h"
#include "core/spectral_table.h"
#include "pipeline/job_log.h"
#include "spectralize/core/error.h"
#include "spectralize/core/spectralizer.h"
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

/// A colour given as "R,G,B".
struct Rgb {
  double r, g, b;
  std::string text;  // as given
};

/// Parses --color's "R,G,B": three finite numbers (spaces around them allowed); UsageError
/// naming the value and the slip otherwise. Cost: O(length).
Rgb parse_rgb(const std::string& text);

/// What every --color command needs: the spectralizer settings (mode auto meaning emission),
/// the parsed colours, the config, the transform of --colorspace (default: the config's
/// scene_linear role) to XYZ and the RGB frame of its exact table (pipeline/render_table.h).
/// UsageError for a mistake. Cost: parsing the config, ~ms.
struct ColourInputs {
  SpectralizerSettings settings;
  std::vector<Rgb> colours;
  std::shared_ptr<const ColourSpaces> spaces;
  ColourTransform to_xyz;
  Mat3 frame;
};
ColourInputs colour_inputs(const Options& options);

/// The spectrum of one --color value: the exact table's (`table`; the spectra images and a
/// renderer's table file give) or, with `table` null (--method exact), a direct solve with the
/// model's details. Warns on stderr when it was out of gamut and mapped (and says when a
/// reflectance was brighter than white), reports an error and sets `status` to kExitFailure
/// when it is invalid. Cost: a cell's node solves on first use (~40 us each), or one solve.
SpectrumResult spectralize_colour(const Spectralizer& spectralizer, SpectralTable* table,
                                  const ColourTransform& to_xyz, const Rgb& colour, int& status);

/// Warnings unless -q; stage details (levels 1 and 2) with -v. Cost: O(1).
LogFn console_log(int verbosity);

/// A progress display on stderr: a bar when stderr is a terminal, a line every few seconds
/// otherwise (farm logs) when verbose. Cost: O(1) per call.
ProgressFn console_progress(int verbosity, const std::string& what);

/// Flushes stdout and throws Error when anything written to it was lost (a full disk, a closed
/// pipe). Cost: a flush.
void check_stdout();

}  // namespace spectralize::tool
