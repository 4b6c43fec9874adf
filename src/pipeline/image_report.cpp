#include "pipeline/image_report.h"

#include <nlohmann/json.hpp>

#include "text/json_text.h"

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

// The space's identity after its name: null where unknown.
void put_identity(Json& j, const SpaceIdentity& id) {
  auto text = [](const std::string& v) { return v.empty() ? Json(nullptr) : Json(v); };
  j["colorspace_interop_id"] = text(id.interop_id);
  j["colorspace_interop_id_source"] = text(id.interop_id_source);
  j["colorspace_encoding"] = text(id.encoding);
}

}  // namespace

SpaceIdentity SpaceIdentity::of(const ColourSpaceFacts& f) {
  SpaceIdentity id;
  id.interop_id = f.interop_id;
  if (!f.interop_id.empty())
    id.interop_id_source = f.interop_id_from_config ? "config" : "measured";
  id.encoding = f.encoding;
  return id;
}

std::vector<std::pair<std::string, std::string>> identity_attributes(const SpaceIdentity& id) {
  return {{"spectralize:colorspaceInteropID", id.interop_id},
          {"spectralize:colorspaceInteropIDSource", id.interop_id_source},
          {"spectralize:colorspaceEncoding", id.encoding}};
}

SpaceIdentity identity_from_attributes(const std::map<std::string, std::string>& strings) {
  auto get = [&](const char* name) {
    auto it = strings.find(name);
    return it == strings.end() ? std::string() : it->second;
  };
  return {get("spectralize:colorspaceInteropID"), get("spectralize:colorspaceInteropIDSource"),
          get("spectralize:colorspaceEncoding")};
}

Json identity_record(const SpaceIdentity& id) {
  Json j;
  put_identity(j, id);
  return j;
}

std::vector<std::string> count_warnings(const PixelCounts& c, const std::string& subject,
                                        const std::string& noun, const OptionNames& names) {
  std::vector<std::string> w;
  const std::string n = " " + noun;
  if (c.invalid > 0)
    w.push_back(subject + ": " + std::to_string(c.invalid) + n +
                " are NaN or infinite: written as zero spectra");
  if (c.alpha_invalid > 0)
    w.push_back(subject + ": " + std::to_string(c.alpha_invalid) + n +
                " have an alpha that is NaN, infinite or outside 0..1: written clamped to 0..1 "
                "(NaN as 0)");
  const std::uint64_t mapped = c.negative + c.outside_locus + c.outside_solid;
  if (mapped > 0)
    w.push_back(subject + ": " + std::to_string(mapped) + n + " out of gamut and mapped (" +
                std::to_string(c.negative) + " negative luminance -> black, " +
                std::to_string(c.outside_locus) + " outside the spectral locus, " +
                std::to_string(c.outside_solid) + " outside the reflectance solid)");
  if (c.brighter_than_white > 0)
    w.push_back(subject + ": " + std::to_string(c.brighter_than_white) + n +
                " are brighter than a white surface (reflectances are 0..1; is this light, " +
                names("mode") +
                " emission, or data in other units?): dimmed into the "
                "reflectance solid");
  if (c.half_overflow > 0)
    w.push_back(subject + ": " + std::to_string(c.half_overflow) + n +
                " have samples above HALF's maximum 65504 and were clamped; use " +
                names("format") + " float to keep them");
  return w;
}

std::vector<std::pair<std::string, double>> count_attributes(const PixelCounts& c) {
  auto d = [](std::uint64_t v) { return static_cast<double>(v); };
  return {{"invalidPixels", d(c.invalid)},
          {"invalidAlphaPixels", d(c.alpha_invalid)},
          {"negativeLuminancePixels", d(c.negative)},
          {"outsideLocusPixels", d(c.outside_locus)},
          {"outsideSolidPixels", d(c.outside_solid)},
          {"brighterThanWhitePixels", d(c.brighter_than_white)},
          {"halfOverflowPixels", d(c.half_overflow)}};
}

PixelCounts counts_from_attributes(const std::map<std::string, double>& a) {
  auto get = [&](const char* name) -> std::uint64_t {
    auto it = a.find(std::string("spectralize:") + name);
    return it == a.end() || !(it->second >= 0) ? 0 : static_cast<std::uint64_t>(it->second);
  };
  PixelCounts c;
  c.invalid = get("invalidPixels");
  c.alpha_invalid = get("invalidAlphaPixels");
  c.negative = get("negativeLuminancePixels");
  c.outside_locus = get("outsideLocusPixels");
  c.outside_solid = get("outsideSolidPixels");
  c.brighter_than_white = get("brighterThanWhitePixels");
  c.half_overflow = get("halfOverflowPixels");
  return c;
}

Json report_record(const ImageReport& r) {
  Json j;
  put_path(j, "input", r.input);
  put_path(j, "output", r.output);
  j["input_format"] = r.input_format;
  j["width"] = r.width;
  j["height"] = r.height;
  j["input_mip_levels"] = r.mip_levels;
  j["input_subimages"] = r.subimages;
  j["input_tiled"] = r.tiled_input;
  j["colorspace"] = r.colorspace;
  j["colorspace_reason"] = r.colorspace_reason;
  put_identity(j, r.colorspace_identity);
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
    put_path(j["cache"], "file", r.cache_file);
    j["cache"]["status"] = r.cache_status;
  }
  j["warnings"] = r.warnings;
  j["seconds"] = {{"setup", r.seconds_setup},
                  {"convert", r.seconds_convert},
                  {"write", r.seconds_write},
                  {"total", r.seconds_total}};
  return j;
}

std::string report_json(const ImageReport& r, int indent) {
  return dump_json(report_record(r), indent);
}

std::string report_json(const ToRgbReport& r, int indent) {
  Json j;
  put_path(j, "input", r.input);
  put_path(j, "output", r.output);
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
  put_identity(j, r.colorspace_identity);
  put_settings(j, r.settings, kToRgb);
  j["pixels"] = r.pixels;
  j["invalid_pixels"] = r.invalid_pixels;
  j["half_overflow_pixels"] = r.half_overflow_pixels;
  j["float_overflow_pixels"] = r.float_overflow_pixels;
  j["clipped_pixels"] = r.clipped_pixels;
  j["warnings"] = r.warnings;
  j["seconds"] = r.seconds;
  return dump_json(j, indent);
}

}  // namespace spectralize
