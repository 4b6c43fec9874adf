#pragma once
// The main job: an RGB image (anything OpenImageIO reads) in, a spectral OpenEXR out, streamed
// in strips of scanlines through OCIO, the exact spectralizer's interpolating table and OIIO's
// writer. No OIIO or OCIO types in this header.

#include <cstdint>
#include <functional>
#include <string>

#include "core/spectral_table.h"
#include "core/spectralizer.h"

namespace spectralize {

struct ImageJobSettings {
  std::string input, output;
  std::string colorspace;     // empty: from the file's metadata, else by data type
  std::string mode = "auto";  // emission | reflectance | auto (float: emission, int: reflectance)
  SpectralizerSettings spectral;  // grid, observer, illuminant, filter (mode set by the job)
  bool half = true;               // HALF or FLOAT samples
  std::string compression = "zip";
  int tile = 0;  // 0: scanlines; else tiles of tile x tile
  SpectralTable::Method method = SpectralTable::Method::table;
  std::string cache_dir;  // empty: no persistent cache
  int threads = 0;        // 0: all cores
  std::string config;     // OCIO config (empty: $OCIO, else shipped)
  std::string date_time;  // fixed DateTime attribute (byte-stable files), else now
};

/// Everything the job measured, for the report and the console.
struct ImageReport {
  std::string input, output, input_format;
  std::string colorspace, colorspace_reason;
  std::string mode, mode_reason;
  std::string wavelengths, observer, illuminant, filter, method, sample_format, compression;
  std::string model, emission_basis;  // filter empty for the smooth model, emission_basis for
                                      // reflectances
  int width = 0, height = 0, input_channels = 0, bands = 0;
  bool alpha = false;
  std::uint64_t pixels = 0;
  std::uint64_t invalid_pixels = 0;             // NaN / Inf
  std::uint64_t negative_pixels = 0;            // negative luminance (out of gamut, made black)
  std::uint64_t outside_locus_pixels = 0;       // mapped into the spectral locus
  std::uint64_t outside_solid_pixels = 0;       // reflectance: mapped into the reflectance solid
  std::uint64_t negative_component_pixels = 0;  // some RGB component < 0 (information)
  std::uint64_t black_pixels = 0;
  std::uint64_t half_overflow_pixels = 0;  // a sample above HALF's 65504 (clamped)
  double max_relative_xyz_error = 0;       // of the written samples vs each pixel's target
  double mean_relative_xyz_error = 0;
  std::uint64_t error_pixels = 0;  // pixels the errors are measured on (non-black)
  TableStats cache;
  std::string cache_file, cache_status;  // persistent cache: path, "loaded"/"new"/why rebuilt
  double seconds_setup = 0, seconds_convert = 0, seconds_write_close = 0, seconds_total = 0;

  /// out_of_gamut_pixels: all kinds together. Cost: O(1).
  std::uint64_t out_of_gamut_pixels() const {
    return negative_pixels + outside_locus_pixels + outside_solid_pixels;
  }
};

/// Progress: pixels done of pixels total.
using ProgressFn = std::function<void(std::uint64_t done, std::uint64_t total)>;
/// Messages for people (warnings, -v details): level 0 warning, 1 info, 2 detail.
using LogFn = std::function<void(int level, const std::string& message)>;

/// The reverse job: a spectral OpenEXR (any writer's) to RGB(A).
struct ToRgbSettings {
  std::string input, output;
  std::string colorspace = "Linear Rec.709 (sRGB)";
  std::string observer = "cie1931";
  std::string illuminant = "D65";  // reflective (T) files are seen under it
  bool half = true;
  std::string compression = "zip";
  int threads = 0;
  std::string config;
  std::string date_time;
};

struct ToRgbReport {
  std::string input, output, colorspace, kind;  // kind: "emissive" or "reflective"
  int width = 0, height = 0, bands = 0;
  double first_nm = 0, last_nm = 0;
  bool polarised = false;  // S1..S3 were present (S0 used)
  double seconds = 0;
};

/// Runs the reverse job, streamed and written like run_image_job. Throws Error naming the file
/// (including for files without spectral channels or with inconsistent ones).
/// Cost: O(pixels x bands).
ToRgbReport run_to_rgb_job(const ToRgbSettings& settings, const ProgressFn& progress,
                           const LogFn& log);

/// Runs the job. Writes to a temporary file beside the output and renames it at the end, so
/// the output is never partial; removes the temporary file on failure. Throws Error naming the
/// file and the reason. Cost: O(pixels x bands), plus node solves on first use.
ImageReport run_image_job(const ImageJobSettings& settings, const ProgressFn& progress,
                          const LogFn& log);

}  // namespace spectralize
