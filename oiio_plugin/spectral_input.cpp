// spectral.imageio.so: an OpenImageIO reader for ".spectral" recipes, so stock OIIO tools
// (oiiotool, maketx, iinfo, ...) can spectralize RGB images or turn spectral EXRs into RGB.
// A thin adapter: all conversion is the spectralize library's (ImageConversion,
// RgbFromSpectral); this file only parses the recipe and serves scanlines.

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <Imath/half.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "classify/input_interpretation.h"
#include "colour/colour_space.h"
#include "imagefile/image_reader.h"
#include "imagefile/output_metadata.h"
#include "imagefile/safe_output.h"
#include "pipeline/image_conversion.h"
#include "pipeline/job_plan.h"
#include "pipeline/rgb_conversion.h"
#include "settings/recipe.h"
#include "spectralize/core/error.h"
#include "spectralize/version.h"

OIIO_PLUGIN_NAMESPACE_BEGIN

namespace {

namespace fs = std::filesystem;

constexpr int kStripRows = 64;  // rows converted at a time

// Reads at most `limit` + 1 bytes of a regular file (never blocks on a FIFO or a device).
bool read_text(const std::string& path, std::string& text, std::size_t limit) {
  try {
    spectralize::check_readable_file(path, "");
  } catch (const spectralize::Error&) {
    return false;
  }
  std::ifstream f(path, std::ios::binary);
  if (!f) return false;
  text.assign(limit + 1, '\0');
  f.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(f.gcount()));
  return true;
}

}  // namespace

class SpectralInput final : public ImageInput {
 public:
  SpectralInput() = default;
  ~SpectralInput() override { close(); }
  const char* format_name() const override { return "spectral"; }
  int supports(string_view feature) const override {
    return feature == "arbitrary_metadata" || feature == "exif";
  }
  bool valid_file(const std::string& filename) const override;
  bool open(const std::string& name, ImageSpec& newspec) override {
    return open(name, newspec, ImageSpec());
  }
  bool open(const std::string& name, ImageSpec& newspec, const ImageSpec& config) override;
  bool close() override;
  bool read_native_scanline(int subimage, int miplevel, int y, int z, void* data) override;

 private:
  bool fill_strip(int y);  // converts the strip of rows holding y into strip_

  std::string recipe_path_;
  std::unique_ptr<spectralize::ImageReader> source_;
  spectralize::Settings settings_;
  bool cache_write_ = false;  // the recipe (or "spectral:cache_write") asked to save the cache
  // RGB -> spectral
  std::unique_ptr<spectralize::ImageConversion> conversion_;
  // spectral -> RGB
  std::unique_ptr<spectralize::RgbConversion> to_rgb_;
  // The current strip of converted rows, as floats.
  int strip_y0_ = 0, strip_y1_ = 0;
  std::vector<float> in_rows_, strip_;
};

bool SpectralInput::valid_file(const std::string& filename) const {
  // Cheap and strict: the extension, a small regular file, a JSON object with a string "source".
  if (!Strutil::iends_with(filename, ".spectral")) return false;
  std::string text;
  if (!read_text(filename, text, spectralize::kMaxRecipeBytes)) return false;
  return spectralize::looks_like_recipe(text);
}

bool SpectralInput::open(const std::string& name, ImageSpec& newspec, const ImageSpec& config) {
  close();
  recipe_path_ = name;
  std::string text;
  if (!read_text(name, text, spectralize::kMaxRecipeBytes)) {
    errorfmt("'{}': cannot read the recipe (a missing, unreadable or non-regular file)", name);
    return false;
  }
  // Options as "spectral:<key>" attributes of the open configuration (OIIO's convention).
  std::map<std::string, std::string> overrides;
  for (const auto& p : config.extra_attribs) {
    const std::string attr = p.name().string();
    if (Strutil::starts_with(attr, "spectral:")) overrides[attr.substr(9)] = p.get_string();
  }
  std::error_code ec;
  const std::string key = fs::weakly_canonical(fs::absolute(name), ec).string();
  try {
    // This recipe joins the thread's chain of recipes being opened: a source that leads back to
    // one of them, or a chain deeper than the limit, is refused here (docs/DESIGN.md §9).
    const spectralize::RecipeChainLink link(name);
    spectralize::Recipe recipe = spectralize::parse_recipe(text, name, overrides);
    if (fs::weakly_canonical(fs::absolute(recipe.source), ec).string() == key) {
      errorfmt("'{}': the recipe's source is the recipe itself", name);
      return false;
    }
    if (!fs::exists(recipe.source, ec)) {
      errorfmt("'{}': source '{}' does not exist", name, recipe.source);
      return false;
    }
    settings_ = recipe.settings;
    // A reader writes nothing unless asked (docs/DESIGN.md §9): the recipe's node cache is
    // read if its folder exists, never created, and saved only with "cache_write": "yes".
    cache_write_ = recipe.cache_write;
    if (!cache_write_ && !settings_.cache_dir.empty() &&
        !fs::is_directory(settings_.cache_dir, ec)) {
      settings_.cache_dir.clear();
      spectralize::set_aside(settings_, *spectralize::find_setting("cache"));
    }
    auto log = [](int, const std::string&) {};  // the plugin has no console: errors only
    // The recipe's keys name the options in messages.
    const spectralize::OptionNames names{"", "the recipe's output"};
    if (recipe.to_rgb) {
      source_ = std::make_unique<spectralize::ImageReader>(recipe.source, 4);
      const auto plan =
          spectralize::planned_input(spectralize::plan_to_rgb(settings_, "", false, true, names),
                                     recipe.source, source_->spec());
      to_rgb_ =
          std::make_unique<spectralize::RgbConversion>(plan, source_->spec(), "", nullptr, log);
      m_spec = to_rgb_->output_spec();
    } else {
      source_ = std::make_unique<spectralize::ImageReader>(
          recipe.source, spectralize::spectral_output_channels(settings_), true);
      const auto plan = spectralize::planned_input(
          spectralize::plan_to_spectral(settings_, "", names), recipe.source, source_->spec());
      conversion_ = std::make_unique<spectralize::ImageConversion>(
          plan, source_->spec(), source_->format_name(), source_->straight_alpha(), log);
      m_spec = conversion_->output_spec();
    }
    // Scanlines only: a reader presents the image; tiles are the writer's business.
    m_spec.tile_width = m_spec.tile_height = m_spec.tile_depth = 0;
  } catch (const std::exception& e) {
    // A loop or an over-deep chain met further in is reported whole, as its first recipe
    // says it, rather than wrapped once per level.
    const std::string& chain = spectralize::RecipeChainLink::chain_failure();
    errorfmt("{}", chain.empty() ? std::string(e.what()) : chain);
    conversion_.reset();
    to_rgb_.reset();
    source_.reset();
    return false;
  }
  newspec = m_spec;
  return true;
}

bool SpectralInput::close() {
  if (conversion_) conversion_->finish([](int, const std::string&) {}, cache_write_);
  conversion_.reset();
  to_rgb_.reset();
  source_.reset();
  strip_y0_ = strip_y1_ = 0;
  return true;
}

bool SpectralInput::fill_strip(int y) {
  const ImageSpec& src = source_->spec();
  const int row = y - src.y;
  const int rows = source_->aligned_rows(kStripRows);
  const int y0 = (row / rows) * rows, y1 = std::min(y0 + rows, src.height);
  const std::size_t n = static_cast<std::size_t>(src.width) * (y1 - y0);
  in_rows_.resize(n * src.nchannels);
  strip_.resize(n * m_spec.nchannels);
  try {
    source_->read_rows(y0, y1, in_rows_.data());
    if (conversion_)
      conversion_->convert(in_rows_.data(), n, strip_.data());
    else
      to_rgb_->convert(in_rows_.data(), n, strip_.data());
  } catch (const std::exception& e) {
    errorfmt("'{}': {}", recipe_path_, e.what());
    strip_y0_ = strip_y1_ = 0;
    return false;
  }
  strip_y0_ = src.y + y0;
  strip_y1_ = src.y + y1;
  return true;
}

bool SpectralInput::read_native_scanline(int subimage, int miplevel, int y, int /*z*/, void* data) {
  lock_guard lock(*this);
  if (!source_ || subimage != 0 || miplevel != 0 || y < m_spec.y || y >= m_spec.y + m_spec.height)
    return false;
  if (y < strip_y0_ || y >= strip_y1_)
    if (!fill_strip(y)) return false;
  const std::size_t values = static_cast<std::size_t>(m_spec.width) * m_spec.nchannels;
  const float* row = strip_.data() + static_cast<std::size_t>(y - strip_y0_) * values;
  // Native data is what the CLI would write: HALF (already rounded by the converter) or FLOAT.
  if (m_spec.format == TypeDesc::HALF) {
    auto* out = static_cast<Imath::half*>(data);
    for (std::size_t i = 0; i < values; ++i) out[i] = Imath::half(row[i]);
  } else {
    std::copy(row, row + values, static_cast<float*>(data));
  }
  return true;
}

OIIO_PLUGIN_NAMESPACE_END

OIIO_PLUGIN_EXPORTS_BEGIN

OIIO_EXPORT int spectral_imageio_version = OIIO_PLUGIN_VERSION;

OIIO_EXPORT const char* spectral_imageio_library_version() {
  return "spectralize " SPECTRALIZE_VERSION;
}

OIIO_EXPORT OIIO::ImageInput* spectral_input_imageio_create() {
  return new OIIO::SpectralInput;
}

OIIO_EXPORT const char* spectral_input_extensions[] = {"spectral", nullptr};

OIIO_PLUGIN_EXPORTS_END
