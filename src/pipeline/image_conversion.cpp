#include "pipeline/image_conversion.h"

#include <filesystem>
#include <nlohmann/json.hpp>

#include "classify/input_interpretation.h"
#include "colour/colour_space.h"
#include "imagefile/output_metadata.h"
#include "pipeline/render_table.h"
#include "pipeline/spectral_converter.h"
#include "pipeline/spectral_image_layout.h"
#include "pipeline/table_cache.h"
#include "spectralize/core/error.h"
#include "text/json_text.h"

namespace fs = std::filesystem;

namespace spectralize {

struct ImageConversion::Parts {
  std::unique_ptr<Spectralizer> own_spectralizer;  // when no pool is shared
  std::unique_ptr<SpectralTable> own_table;
  const Spectralizer* spectralizer = nullptr;
  SpectralTable* table = nullptr;
  bool shared = false;  // the pool loads and saves the cache
  std::unique_ptr<SpectralImageLayout> layout;
  std::unique_ptr<SpectralConverter> converter;
  std::string cache_key;
  OptionNames names;  // the caller's spellings, for messages
};

ImageConversion::ImageConversion(const JobPlan& plan, const OIIO::ImageSpec& spec,
                                 const std::string& format_name, bool straight_alpha,
                                 const LogFn& log, const ConversionContext& context)
    : parts_(std::make_unique<Parts>()) {
  if (!plan.decided() || plan.to_rgb)
    throw Error("internal: an image conversion needs a plan decided for its RGB input");
  parts_->names = plan.names;
  const std::string& input = plan.input;
  ImageReport& rep = report_;
  auto warn = [&](const std::string& message) {
    rep.warnings.push_back(message);
    log(0, message);
  };
  rep.input = input;
  rep.input_format = format_name;
  rep.width = spec.width;
  rep.height = spec.height;
  rep.pixels = static_cast<std::uint64_t>(spec.width) * static_cast<std::uint64_t>(spec.height);
  const ColourSpaces& spaces = plan.colour_spaces();
  const InputInterpretation& in = plan.interpretation;
  for (const std::string& w : in.warnings) warn(w);
  rep.colorspace = in.colorspace;
  rep.colorspace_reason = in.colorspace_reason;
  rep.colorspace_identity = SpaceIdentity::of(*in.facts);
  rep.mode_reason = in.mode_reason;
  rep.alpha = in.channels.alpha >= 0;
  rep.straight_alpha = straight_alpha;
  rep.settings = plan.settings;  // mode, colour space and preview space as decided for the file
  Settings& s = rep.settings;
  rep.preview_colorspace = s.preview_colorspace;
  rep.bands = static_cast<int>(s.spectral.grid.size());
  log(1, "'" + input + "': " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
             ", " + std::to_string(spec.nchannels) + " channels, " + spec.format.c_str() + " (" +
             format_name + "); colour space '" + in.colorspace + "' (" + in.colorspace_reason +
             "); mode " + std::string(to_string(in.mode)) + " (" + in.mode_reason + ")");

  Parts& p = *parts_;
  const Mat3 frame = table_frame(spaces, in.colorspace);
  if (TablePool* pool = context.pool) {
    TablePool::Entry& e = pool->get(s, frame, log, p.names("cache"));
    p.spectralizer = e.spectralizer.get();
    p.table = e.table.get();
    p.shared = true;
    rep.cache_file = e.cache_file;
    rep.cache_status = e.cache_status;
  } else {
    p.own_spectralizer = std::make_unique<Spectralizer>(s.spectral);
    p.own_table = std::make_unique<SpectralTable>(*p.own_spectralizer, s.method, frame);
    p.spectralizer = p.own_spectralizer.get();
    p.table = p.own_table.get();
    load_cache(log, warn);
  }

  // The output: previews in the config's scene-linear space (the shipped config: Linear
  // Rec.709), then alpha and the bands.
  std::string date_warning;
  const std::string date_time = output_date_time(date_warning);
  if (!date_warning.empty()) warn(date_warning);
  // Why this colour space and mode, so that whoever reads the file (and an ingest rerun that
  // skips it) can tell; attributes given by the caller come after and win.
  std::map<std::string, std::string> recorded = {
      {"spectralize:colorspaceReason", in.colorspace_reason},
      {"spectralize:modeReason", in.mode_reason}};
  // What the space is beyond its name, where known (an up-to-date record reads it back).
  for (const auto& [name, value] : identity_attributes(rep.colorspace_identity))
    if (!value.empty()) recorded[name] = value;
  std::vector<std::pair<std::string, double>> numbers;
  if (context.record_in_header) {
    nlohmann::ordered_json known = nlohmann::ordered_json::array();
    for (const std::string& w : rep.warnings) known.push_back(utf8_escaped(w));
    recorded[kWarningsAttribute] = dump_json(known);
    for (const auto& [name, value] : count_attributes(PixelCounts{}))
      numbers.emplace_back("spectralize:" + name, value);
  }
  if (context.attributes)
    for (const auto& [name, value] : context.attributes(s)) recorded[name] = value;
  p.layout = spectral_exr_layout({spec, rep.alpha, s, in.colorspace, rep.preview_colorspace, spaces,
                                  date_time, recorded, numbers});
  p.converter = std::make_unique<SpectralConverter>(SpectralConverter::Setup{
      *p.spectralizer, *p.table, in.channels, spec.nchannels, straight_alpha,
      spaces.to_xyz(in.colorspace), spaces.from_xyz(rep.preview_colorspace), *p.layout, s.half,
      s.threads, context.share});
}

// The persistent node cache, keyed by everything the nodes depend on. An unusable cache is
// reported and bypassed or rebuilt, never fatal and never trusted.
void ImageConversion::load_cache(const LogFn& log,
                                 const std::function<void(const std::string&)>& warn) {
  ImageReport& rep = report_;
  const Settings& s = rep.settings;
  Parts& p = *parts_;
  if (s.cache_dir.empty() || s.method != SpectralTable::Method::table) return;
  std::error_code ec;
  fs::create_directories(s.cache_dir, ec);
  if (!fs::is_directory(s.cache_dir, ec)) {
    warn(p.names("cache") + " '" + s.cache_dir +
         "': not a folder that can be created; running without a persistent cache");
    return;
  }
  p.cache_key = table_cache_key(s, p.table->layout());
  rep.cache_file = table_cache_file(s.cache_dir, p.cache_key);
  const std::string why = load_table_cache(*p.table, rep.cache_file, p.cache_key);
  if (!why.empty()) {
    rep.cache_status = "rebuilt: " + why;
    warn("cache '" + rep.cache_file + "' ignored and rebuilt: " + why);
  } else {
    rep.cache_status = p.table->stats().nodes_loaded > 0 ? "loaded" : "new";
  }
  log(2, "cache '" + rep.cache_file + "': " + rep.cache_status + ", " +
             std::to_string(p.table->stats().nodes_loaded) + " nodes");
}

ImageConversion::~ImageConversion() = default;

std::vector<std::string> recorded_warnings(const std::map<std::string, std::string>& strings,
                                           const std::map<std::string, double>& doubles,
                                           const std::string& input, const OptionNames& names) {
  std::vector<std::string> out;
  if (auto it = strings.find(kWarningsAttribute); it != strings.end()) {
    const auto j = nlohmann::ordered_json::parse(it->second, nullptr, false);
    if (j.is_array())
      for (const auto& w : j)
        if (w.is_string()) out.push_back(w.get<std::string>());
  }
  for (const std::string& w :
       count_warnings(counts_from_attributes(doubles), "'" + input + "'", "pixels", names))
    out.push_back(w);
  return out;
}

const OIIO::ImageSpec& ImageConversion::output_spec() const {
  return parts_->layout->spec();
}

void ImageConversion::convert(const float* in, std::size_t n, float* out) {
  parts_->converter->convert(in, n, out);
}

const ImageReport& ImageConversion::finish(const LogFn& log, bool save_cache) {
  Parts& p = *parts_;
  report_.counts = p.converter->counts();
  report_.cache = p.table->stats();
  // What was not a plain exact conversion, for people and for the report.
  for (const std::string& w :
       count_warnings(report_.counts, "'" + report_.input + "'", "pixels", parts_->names)) {
    report_.warnings.push_back(w);
    log(0, w);
  }
  if (save_cache && !p.shared && !report_.cache_file.empty() && p.table->dirty()) {
    const std::string why = save_table_cache(*p.table, report_.cache_file, p.cache_key);
    if (!why.empty()) {
      const std::string message = "cache '" + report_.cache_file + "' not saved: " + why;
      report_.warnings.push_back(message);
      log(0, message);
    }
  }
  return report_;
}

}  // namespace spectralize
