#pragma once
// What a conversion did and measured, for the console, the --report JSON, the ingest manifest
// and the Python module. The settings part is generated from the schema (docs/DESIGN.md §8).

#include <cstdint>
#include <map>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <utility>
#include <vector>

#include "colour/colour_space.h"
#include "core/tables/spectral_table.h"
#include "pipeline/job_plan.h"
#include "pipeline/spectral_converter.h"
#include "settings/settings.h"

namespace spectralize {

/// What a report says of a colour space beyond its name (docs/DESIGN.md §9): the Color Interop
/// Forum's ID, stated by the config (OCIO 2.5) or measured, and the config's encoding; "" where
/// neither is known. Reports, manifests and the spectral file's header carry it.
struct SpaceIdentity {
  std::string interop_id;
  std::string interop_id_source;  // "config" or "measured" ("" without an ID)
  std::string encoding;           // the config's ("scene-linear", "sdr-video", ...)
  /// The identity the facts give. Cost: O(1).
  static SpaceIdentity of(const ColourSpaceFacts& facts);
};

/// The spectral file header's attributes of an identity ("spectralize:colorspaceInteropID",
/// "...InteropIDSource", "...Encoding"), in that order, values "" where unknown. Cost: O(1).
std::vector<std::pair<std::string, std::string>> identity_attributes(const SpaceIdentity& id);

/// The identity those attributes record (absent ones ""). Cost: O(1).
SpaceIdentity identity_from_attributes(const std::map<std::string, std::string>& strings);

/// The identity as a report's fields: colorspace_interop_id, colorspace_interop_id_source and
/// colorspace_encoding, null where unknown. Cost: O(1).
nlohmann::ordered_json identity_record(const SpaceIdentity& id);

struct ImageReport {
  std::string input, output, input_format;
  int width = 0, height = 0, bands = 0;
  int mip_levels = 1, subimages = 1;  // of the input: level 0 of subimage 0 is converted
  bool tiled_input = false;
  std::string colorspace, colorspace_reason;  // of the input
  SpaceIdentity colorspace_identity;
  std::string mode_reason;
  std::string preview_colorspace;
  Settings settings;  // as used (mode resolved in settings.spectral.mode)
  bool alpha = false, straight_alpha = false;
  std::uint64_t pixels = 0;
  PixelCounts counts;
  TableStats cache;
  std::string cache_file, cache_status;  // persistent cache: path, "loaded"/"new"/why rebuilt
  std::vector<std::string> warnings;     // everything said at level 0, each naming the file
  double seconds_setup = 0, seconds_convert = 0, seconds_write = 0, seconds_total = 0;

  /// All out-of-gamut pixels together. Cost: O(1).
  std::uint64_t out_of_gamut_pixels() const {
    return counts.negative + counts.outside_locus + counts.outside_solid;
  }
  /// Mean relative XYZ error of the written samples. Cost: O(1).
  double mean_error() const {
    return counts.error_pixels ? counts.sum_error / counts.error_pixels : 0.0;
  }
};

/// The reverse job's report.
struct ToRgbReport {
  std::string input, output, output_format, colorspace, kind;  // kind: emissive / reflective
  SpaceIdentity colorspace_identity;  // of the space written (a display's view: its space)
  int width = 0, height = 0, bands = 0;
  double first_nm = 0, last_nm = 0;
  bool polarised = false;  // S1..S3 were present (S0 used)
  int mip_levels = 1, subimages = 1;
  Settings settings;
  std::uint64_t pixels = 0, invalid_pixels = 0, half_overflow_pixels = 0, clipped_pixels = 0;
  std::uint64_t float_overflow_pixels = 0;  // float output: beyond float's range (clamped)
  std::vector<std::string> warnings;
  double seconds = 0;
};

/// The warnings a conversion's counts call for (NaN or infinite colours, bad alpha, out of
/// gamut, brighter than white, HALF overflow), each starting with `subject` ("'albedo.png'",
/// "rgb") and counting `noun` ("pixels", "colours"); options spelt as `names` does. Cost: O(1).
std::vector<std::string> count_warnings(const PixelCounts& counts, const std::string& subject,
                                        const std::string& noun, const OptionNames& names);

/// The counts a spectral file's header records (as "spectralize:<name>" double attributes,
/// exact below 2^53), by name: the ones count_warnings speaks of. Cost: O(1).
std::vector<std::pair<std::string, double>> count_attributes(const PixelCounts& counts);

/// The counts read back from those attributes (absent ones are 0). Cost: O(attributes).
PixelCounts counts_from_attributes(const std::map<std::string, double>& attributes);

/// The report as a JSON object: the one record every front end takes its fields from (--report,
/// the ingest manifest, the Python module). Cost: O(report).
nlohmann::ordered_json report_record(const ImageReport& report);
/// The report as JSON text (indent < 0: one line). Cost: O(report).
std::string report_json(const ImageReport& report, int indent = 2);
/// The reverse job's report as JSON text. Cost: O(report).
std::string report_json(const ToRgbReport& report, int indent = 2);

}  // namespace spectralize
