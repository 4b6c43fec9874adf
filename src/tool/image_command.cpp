// spectralize INPUT -o OUTPUT.exr: the image job with its console output and JSON report.

#include <fmt/core.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "core/error.h"
#include "io/colour_space.h"
#include "io/image_job.h"
#include "tool/flags.h"
#include "tool/options.h"

namespace spectralize::tool {

namespace {

using Json = nlohmann::ordered_json;

// Compression methods of OpenEXR that OIIO's writer accepts.
constexpr const char* kCompressions[] = {"none",  "rle", "zips", "zip",  "piz",
                                         "pxr24", "b44", "b44a", "dwaa", "dwab"};

// A progress bar on stderr (only when it is a terminal): fraction, pixel rate and ETA.
class ProgressBar {
 public:
  explicit ProgressBar(bool enabled) : enabled_(enabled) {}
  void update(std::uint64_t done, std::uint64_t total) {
    if (!enabled_ || total == 0) return;
    const double t = std::chrono::duration<double>(Clock::now() - start_).count();
    const double f = static_cast<double>(done) / static_cast<double>(total);
    const double rate = t > 0 ? static_cast<double>(done) / t / 1e6 : 0;
    const double eta = f > 0 ? t * (1 - f) / f : 0;
    const int filled = static_cast<int>(f * 30);
    fmt::print(stderr, "\r[{:<30}] {:3.0f}%  {:.2f} Mpixel/s  ETA {:.0f} s ",
               std::string(filled, '#'), 100 * f, rate, eta);
    if (done == total) fmt::print(stderr, "\n");
    std::fflush(stderr);
  }

 private:
  using Clock = std::chrono::steady_clock;
  bool enabled_;
  Clock::time_point start_ = Clock::now();
};

Json report_json(const ImageReport& r) {
  Json j;
  j["input"] = r.input;
  j["output"] = r.output;
  j["input_format"] = r.input_format;
  j["width"] = r.width;
  j["height"] = r.height;
  j["colorspace"] = r.colorspace;
  j["colorspace_reason"] = r.colorspace_reason;
  j["mode"] = r.mode;
  j["mode_reason"] = r.mode_reason;
  j["wavelengths"] = r.wavelengths;
  j["bands"] = r.bands;
  j["observer"] = r.observer;
  if (!r.illuminant.empty()) j["illuminant"] = r.illuminant;
  if (!r.filter.empty()) j["filter"] = r.filter;  // the paper model's only
  j["model"] = r.model;
  if (!r.emission_basis.empty()) j["emission_basis"] = r.emission_basis;
  j["method"] = r.method;
  j["format"] = r.sample_format;
  j["compression"] = r.compression;
  j["alpha"] = r.alpha;
  j["pixels"] = r.pixels;
  j["out_of_gamut_pixels"] = r.out_of_gamut_pixels();
  j["out_of_gamut"] = {{"negative_luminance", r.negative_pixels},
                       {"outside_locus", r.outside_locus_pixels},
                       {"outside_reflectance_solid", r.outside_solid_pixels}};
  j["invalid_pixels"] = r.invalid_pixels;
  j["negative_component_pixels"] = r.negative_component_pixels;
  j["black_pixels"] = r.black_pixels;
  j["half_overflow_pixels"] = r.half_overflow_pixels;
  j["max_relative_xyz_error"] = r.max_relative_xyz_error;
  j["mean_relative_xyz_error"] = r.mean_relative_xyz_error;
  j["cache"] = {{"nodes_computed", r.cache.nodes_computed},
                {"nodes_reused", r.cache.nodes_loaded},
                {"nodes_infeasible", r.cache.nodes_infeasible},
                {"fallbacks", r.cache.fallback_solves},
                {"fallback_hits", r.cache.fallback_hits}};
  if (!r.cache_file.empty()) {
    j["cache"]["file"] = r.cache_file;
    j["cache"]["status"] = r.cache_status;
  }
  j["seconds"] = {{"setup", r.seconds_setup},
                  {"convert", r.seconds_convert},
                  {"write", r.seconds_write_close},
                  {"total", r.seconds_total}};
  return j;
}

// Writes the report beside its destination and renames it, like the image.
void write_report(const std::string& path, const Json& j) {
  const std::string tmp = path + ".tmp-" + std::to_string(::getpid());
  {
    std::ofstream f(tmp);
    if (!f) throw Error("--report '" + path + "': cannot write");
    f << j.dump(2) << "\n";
    if (!f) throw Error("--report '" + path + "': cannot write");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw Error("--report '" + path + "': cannot write");
  }
}

void check_compression(const std::string& compression) {
  for (const char* c : kCompressions)
    if (compression == c) return;
  throw UsageError{fmt::format(
      "--compression '{}': valid: none, rle, zips, zip, piz, pxr24, b44, b44a, dwaa, dwab",
      compression)};
}

// SOURCE_DATE_EPOCH (the reproducible-builds convention) fixes the DateTime attribute, so the
// output is byte-stable; empty means "now".
std::string fixed_date_time() {
  const char* epoch = std::getenv("SOURCE_DATE_EPOCH");
  if (!epoch || !*epoch) return "";
  std::time_t t = static_cast<std::time_t>(std::strtoll(epoch, nullptr, 10));
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y:%m:%d %H:%M:%S", std::gmtime(&t));
  return buf;
}

// Warnings unless -q; stage details (levels 1 and 2) with -v.
LogFn console_log(int verbosity) {
  return [verbosity](int level, const std::string& message) {
    if (level == 0 && verbosity > 0)
      fmt::print(stderr, "spectralize WARNING: {}\n", message);
    else if (level > 0 && verbosity >= 2)
      fmt::print(stderr, "spectralize: {}\n", message);
  };
}

// --format for images: HALF (default) or FLOAT samples.
bool half_samples(const Options& opt) {
  const std::string format = opt.format.empty() ? "half" : opt.format;
  if (format != "half" && format != "float")
    throw UsageError{
        fmt::format("--format '{}': valid formats for images are half, float", format)};
  return format == "half";
}

bool ends_with_exr(const std::string& path) {
  if (path.size() < 4) return false;
  std::string ext = path.substr(path.size() - 4);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".exr";
}

}  // namespace

int run_to_rgb(const Options& opt) {
  if (opt.output.empty()) throw UsageError{"-o OUTPUT.exr is required"};
  if (!ends_with_exr(opt.output))
    throw UsageError{fmt::format("-o '{}': the output is an OpenEXR file (.exr)", opt.output)};
  ToRgbSettings job;
  job.input = opt.to_rgb;
  job.output = opt.output;
  job.config = opt.config;
  const ColourSpaces spaces = load_config(opt);
  job.colorspace = flag_value("--colorspace", [&] {
    return spaces.resolve(opt.colorspace.empty() ? std::string(kDefaultColourSpace)
                                                 : opt.colorspace);
  });
  job.observer = flag_value("--observer", [&] { return Observer::get(opt.observer).name; });
  job.illuminant = flag_value("--illuminant", [&] { return Illuminant::get(opt.illuminant).name; });
  job.half = half_samples(opt);
  check_compression(opt.compression);
  job.compression = opt.compression;
  if (!opt.threads.empty()) job.threads = parse_int_flag("--threads", opt.threads, 1, 1024);
  job.date_time = fixed_date_time();
  const int verbosity = opt.verbosity;
  LogFn log = console_log(verbosity);
  ProgressBar bar(::isatty(STDERR_FILENO) && verbosity > 0);
  ProgressFn progress = [&](std::uint64_t done, std::uint64_t total) { bar.update(done, total); };
  ToRgbReport r = run_to_rgb_job(job, progress, log);
  if (verbosity > 0)
    fmt::print(stderr,
               "spectralize: '{}' -> '{}': {}x{}, {} {} bands {}..{} nm{} -> {}{}; {:.2f} s\n",
               r.input, r.output, r.width, r.height, r.bands, r.kind, r.first_nm, r.last_nm,
               r.polarised ? " (polarised: S0 used)" : "", r.colorspace,
               r.kind == "reflective" ? " under " + job.illuminant : std::string(), r.seconds);
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
        fmt::format("-o '{}': the output is a spectral OpenEXR file (.exr)", opt.output)};
  ImageJobSettings job;
  job.input = opt.inputs[0];
  job.output = opt.output;
  job.colorspace = opt.colorspace;
  job.config = opt.config;
  // The config and the colour space are command-line values: check them up front.
  const ColourSpaces spaces = load_config(opt);
  if (!opt.colorspace.empty())
    job.colorspace = flag_value("--colorspace", [&] { return spaces.resolve(opt.colorspace); });
  job.spectral = spectral_settings(opt);
  job.mode = opt.mode.empty() ? "auto" : opt.mode;
  if (job.mode != "auto") flag_value("--mode", [&] { return parse_mode(job.mode); });
  job.half = half_samples(opt);
  check_compression(opt.compression);
  job.compression = opt.compression;
  if (!opt.tile.empty()) job.tile = parse_int_flag("--tile", opt.tile, 16, 4096);
  if (opt.method != "table" && opt.method != "exact")
    throw UsageError{fmt::format("--method '{}': valid methods are table, exact", opt.method)};
  job.method = opt.method == "table" ? SpectralTable::Method::table : SpectralTable::Method::exact;
  job.cache_dir = opt.cache;
  if (!opt.threads.empty()) job.threads = parse_int_flag("--threads", opt.threads, 1, 1024);
  job.date_time = fixed_date_time();

  const int verbosity = opt.verbosity;
  LogFn log = console_log(verbosity);
  ProgressBar bar(::isatty(STDERR_FILENO) && verbosity > 0);
  ProgressFn progress = [&](std::uint64_t done, std::uint64_t total) { bar.update(done, total); };

  ImageReport r = run_image_job(job, progress, log);

  // Warnings about what was not a plain exact conversion.
  if (r.invalid_pixels > 0)
    log(0, fmt::format("'{}': {} pixels are NaN or infinite: written as zero spectra", r.input,
                       r.invalid_pixels));
  if (r.out_of_gamut_pixels() > 0)
    log(0, fmt::format("'{}': {} pixels out of gamut and mapped ({} negative luminance -> black, "
                       "{} outside the spectral locus, {} outside the reflectance solid)",
                       r.input, r.out_of_gamut_pixels(), r.negative_pixels, r.outside_locus_pixels,
                       r.outside_solid_pixels));
  if (r.half_overflow_pixels > 0)
    log(0, fmt::format("'{}': {} pixels have samples above HALF's maximum 65504 and were clamped; "
                       "use --format float to keep them",
                       r.output, r.half_overflow_pixels));
  if (!opt.report.empty()) write_report(opt.report, report_json(r));
  if (verbosity > 0) {
    fmt::print(stderr,
               "spectralize: '{}' -> '{}': {}x{} {} ({}), {} bands {}, {} {}; out of gamut {}, "
               "invalid {}; max relative XYZ error {:.2g}; {:.2f} s\n",
               r.input, r.output, r.width, r.height, r.mode, r.colorspace, r.bands, r.wavelengths,
               r.sample_format, r.compression, r.out_of_gamut_pixels(), r.invalid_pixels,
               r.max_relative_xyz_error, r.seconds_total);
  }
  if (verbosity >= 2)
    fmt::print(stderr,
               "spectralize: cache: {} nodes computed, {} reused, {} infeasible, {} direct solves, "
               "{} direct hits; seconds: setup {:.3f}, convert {:.3f}, write {:.3f}\n",
               r.cache.nodes_computed, r.cache.nodes_loaded, r.cache.nodes_infeasible,
               r.cache.fallback_solves, r.cache.fallback_hits, r.seconds_setup, r.seconds_convert,
               r.seconds_write_close);
  return kExitOk;
}

}  // namespace spectralize::tool
