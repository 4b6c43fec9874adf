#include "io/image_report.h"

#include <nlohmann/json.hpp>

namespace spectralize {

namespace {

using Json = nlohmann::ordered_json;

// The settings that applied, by the schema's keys and canonical texts.
void put_settings(Json& j, const Settings& s, Command command) {
  for (const auto& [key, value] : describe_settings(s, command)) {
    if (key == "colorspace") continue;  // the job reports the space it chose, with its reason
    j[key] = value;
  }
}

}  // namespace

std::string report_json(const ImageReport& r, int indent) {
  Json j;
  j["input"] = r.input;
  j["output"] = r.output;
  j["input_format"] = r.input_format;
  j["width"] = r.width;
  j["height"] = r.height;
  j["input_mip_levels"] = r.mip_levels;
  j["input_subimages"] = r.subimages;
  j["input_tiled"] = r.tiled_input;
  j["colorspace"] = r.colorspace;
  j["colorspace_reason"] = r.colorspace_reason;
  put_settings(j, r.settings, kImage);
  j["mode_reason"] = r.mode_reason;
  j["bands"] = r.bands;
  j["preview_colorspace"] = r.preview_colorspace;
  j["alpha"] = r.alpha;
  if (r.alpha) j["alpha_straight_in_input"] = r.straight_alpha;
  const PixelCounts& c = r.counts;
  j["pixels"] = r.pixels;
  j["out_of_gamut_pixels"] = r.out_of_gamut_pixels();
  j["out_of_gamut"] = {{"negative_luminance", c.negative},
                       {"outside_locus", c.outside_locus},
                       {"outside_reflectance_solid", c.outside_solid},
                       {"brighter_than_white", c.brighter_than_white}};
  j["invalid_pixels"] = c.invalid;
  j["invalid_alpha_pixels"] = c.alpha_invalid;
  j["negative_component_pixels"] = c.negative_component;
  j["black_pixels"] = c.black;
  j["half_overflow_pixels"] = c.half_overflow;
  j["max_relative_xyz_error"] = c.max_error;
  j["mean_relative_xyz_error"] = r.mean_error();
  j["cache"] = {{"nodes_computed", r.cache.nodes_computed},
                {"nodes_reused", r.cache.nodes_loaded},
                {"nodes_infeasible", r.cache.nodes_infeasible},
                {"fallbacks", r.cache.fallback_solves},
                {"fallback_hits", r.cache.fallback_hits}};
  if (!r.cache_file.empty()) {
    j["cache"]["file"] = r.cache_file;
    j["cache"]["status"] = r.cache_status;
  }
  j["warnings"] = r.warnings;
  j["seconds"] = {{"setup", r.seconds_setup},
                  {"convert", r.seconds_convert},
                  {"write", r.seconds_write},
                  {"total", r.seconds_total}};
  return j.dump(indent);
}

std::string report_json(const ToRgbReport& r, int indent) {
  Json j;
  j["input"] = r.input;
  j["output"] = r.output;
  j["output_format"] = r.output_format;
  j["width"] = r.width;
  j["height"] = r.height;
  j["input_mip_levels"] = r.mip_levels;
  j["kind"] = r.kind;
  j["bands"] = r.bands;
  j["first_nm"] = r.first_nm;
  j["last_nm"] = r.last_nm;
  j["polarised"] = r.polarised;
  j["colorspace"] = r.colorspace;
  put_settings(j, r.settings, kToRgb);
  j["pixels"] = r.pixels;
  j["invalid_pixels"] = r.invalid_pixels;
  j["half_overflow_pixels"] = r.half_overflow_pixels;
  j["clipped_pixels"] = r.clipped_pixels;
  j["warnings"] = r.warnings;
  j["seconds"] = r.seconds;
  return j.dump(indent);
}

}  // namespace spectralize
