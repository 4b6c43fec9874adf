// spectralize INPUT -o OUTPUT.exr and --to-rgb: the streamed jobs with their console output
// and JSON report.

#include <OpenImageIO/imageio.h>
#include <fmt/core.h>

#include <filesystem>
#include <memory>
#include <string>

#include "core/error.h"
#include "io/colour_space.h"
#include "io/image_job.h"
#include "io/input_interpretation.h"
#include "io/safe_output.h"
#include "tool/flags.h"
#include "tool/options.h"

namespace spectralize::tool {

namespace {

// A name whose extension OpenImageIO writes.
bool is_image_path(const std::string& path) {
  auto out = OIIO::ImageOutput::create(path);
  if (!out) (void)OIIO::geterror();
  return out != nullptr;
}

// Formats that store only floats (Radiance HDR, PFM): no integer default.
bool is_float_path(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".hdr" || ext == ".pfm";
}

bool ends_with_exr(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  return ext.size() == 4 && (ext[1] | 32) == 'e' && (ext[2] | 32) == 'x' && (ext[3] | 32) == 'r';
}

// The report's destination, checked (and its temporary file created) before any work: never
// the input or the output under any alias; /dev/stdout and /dev/null work as streams.
std::unique_ptr<AtomicOutput> open_report(const Options& opt, const std::string& input) {
  if (opt.report.empty()) return nullptr;
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path a = fs::weakly_canonical(fs::absolute(opt.report), ec);
  const fs::path b = fs::weakly_canonical(fs::absolute(opt.output), ec);
  if (a == b || same_file(opt.report, opt.output))
    throw Error("--report '" + clip(opt.report) +
                "': is the output file; refusing to overwrite it");
  const std::string inputs[] = {input, opt.output};
  try {
    return std::make_unique<AtomicOutput>(opt.report, inputs, /*allow_stream=*/true);
  } catch (const Error& e) {
    throw Error(std::string("--report ") + e.what());
  }
}

void write_report(AtomicOutput* report, const std::string& json) {
  if (!report) return;
  report->write(json + "\n");
  report->commit();
}

// The config and colour space are command-line values: checked before any work.
Settings checked_settings(const Options& opt) {
  Settings s = opt.settings;
  const ColourSpaces spaces = load_config(opt);
  if (!s.colorspace.empty())
    s.colorspace = flag_value("--colorspace", [&] { return spaces.resolve(s.colorspace); });
  return s;
}

}  // namespace

int run_to_rgb(const Options& opt) {
  if (opt.output.empty()) throw UsageError{"-o OUTPUT is required"};
  if (!is_image_path(opt.output))
    throw UsageError{
        fmt::format("-o '{}': an image file OpenImageIO writes (.exr, .tif, .png, .jpg, .hdr, ...)",
                    clip(opt.output))};
  Settings s = checked_settings(opt);
  const ColourSpaces spaces = load_config(opt);
  if (!s.display.empty() && !s.colorspace.empty())
    throw UsageError{"give --colorspace or --display, not both"};
  if (!s.view.empty() && s.display.empty()) throw UsageError{"--view needs --display"};
  if (!s.display.empty())
    flag_value("--display", [&] { return spaces.display_from_xyz(s.display, s.view); });
  // Files that store integers are display-referred: an encoded space and 8 bits by default.
  const bool integer_file = !ends_with_exr(opt.output) && !is_float_path(opt.output);
  if (integer_file && !opt.given.count("--format") && !opt.given.count("-d")) s.integer_bits = 8;
  if (integer_file && s.integer_bits == 0)
    throw UsageError{
        fmt::format("-o '{}': --format uint8 or uint16 for this file type", clip(opt.output))};
  if (s.colorspace.empty() && s.display.empty())
    s.colorspace = default_colour_space(spaces, !integer_file).first;
  auto report = open_report(opt, opt.to_rgb);
  const LogFn log = console_log(opt.verbosity);
  const ToRgbReport r =
      run_to_rgb_job(opt.to_rgb, opt.output, s, console_progress(opt.verbosity, opt.to_rgb), log);
  write_report(report.get(), report_json(r));
  if (opt.verbosity > 0)
    fmt::print(
        stderr, "spectralize: '{}' -> '{}': {}x{}, {} {} bands {}..{} nm{} -> {}{}; {:.2f} s\n",
        r.input, r.output, r.width, r.height, r.bands, r.kind, r.first_nm, r.last_nm,
        r.polarised ? " (polarised: S0 used)" : "", r.colorspace,
        r.kind == "reflective" ? " under " + s.spectral.illuminant : std::string(), r.seconds);
  return kExitOk;
}

int run_image(const Options& opt) {
  // Validate every flag before any work (exit 2 on a mistake).
  if (opt.inputs.size() != 1)
    throw UsageError{opt.inputs.empty()
                         ? "no input image given"
                         : fmt::format("one input image at a time, got {}", opt.inputs.size())};
  if (opt.output.empty()) throw UsageError{"-o OUTPUT.exr is required"};
  if (!ends_with_exr(opt.output))
    throw UsageError{
        fmt::format("-o '{}': the output is a spectral OpenEXR file (.exr)", clip(opt.output))};
  const std::string& input = opt.inputs[0];
  const Settings s = checked_settings(opt);
  if (s.integer_bits != 0)
    throw UsageError{"--format uint" + std::to_string(s.integer_bits) +
                     ": a spectral OpenEXR stores half or float samples"};
  auto report = open_report(opt, input);
  const LogFn log = console_log(opt.verbosity);
  const ImageReport r =
      run_image_job(input, opt.output, s, console_progress(opt.verbosity, input), log);

  const PixelCounts& c = r.counts;
  write_report(report.get(), report_json(r));
  if (opt.verbosity > 0) {
    fmt::print(stderr,
               "spectralize: '{}' -> '{}': {}x{} {} ({}), {} bands {}, {} {}; out of gamut {}, "
               "invalid {}; max relative XYZ error {:.2g}; {:.2f} s\n",
               r.input, r.output, r.width, r.height, to_string(r.settings.spectral.mode),
               r.colorspace, r.bands, r.settings.spectral.grid.to_string(),
               r.settings.half ? "half" : "float", r.settings.compression, r.out_of_gamut_pixels(),
               c.invalid, c.max_error, r.seconds_total);
  }
  if (opt.verbosity >= 2)
    fmt::print(stderr,
               "spectralize: cache: {} nodes computed, {} reused, {} infeasible, {} direct solves, "
               "{} direct hits; seconds: setup {:.3f}, convert {:.3f}, write {:.3f}\n",
               r.cache.nodes_computed, r.cache.nodes_loaded, r.cache.nodes_infeasible,
               r.cache.fallback_solves, r.cache.fallback_hits, r.seconds_setup, r.seconds_convert,
               r.seconds_write);
  return kExitOk;
}

}  // namespace spectralize::tool
