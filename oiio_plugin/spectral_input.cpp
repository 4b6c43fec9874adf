// spectral.imageio.so: an OpenImageIO reader for ".spectral" recipes, so stock OIIO tools
// (oiiotool, maketx, iinfo, ...) can spectralize RGB images or turn spectral EXRs into RGB.
// A thin adapter: all conversion is the spectralize library's (SpectralConverter,
// RgbFromSpectral); this file only parses the recipe and serves scanlines.

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <Imath/half.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/image_job.h"
#include "io/output_spec.h"
#include "io/recipe.h"
#include "io/rgb_from_spectral.h"
#include "io/spectral_converter.h"

OIIO_PLUGIN_NAMESPACE_BEGIN

namespace {

namespace fs = std::filesystem;

constexpr std::size_t kMaxRecipeBytes = 1 << 20;  // a recipe is a few hundred bytes
constexpr int kStripRows = 64;                    // rows converted at a time

// Recipes being opened on this thread: a recipe whose source leads back to one of them loops.
thread_local std::set<std::string> t_opening;

bool read_text(const std::string& path, std::string& text, std::size_t limit) {
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
  std::unique_ptr<ImageInput> source_;
  // RGB -> spectral
  spectralize::ImageJobSettings job_;
  spectralize::ImageReport report_;
  std::unique_ptr<spectralize::SpectralConverter> converter_;
  // spectral -> RGB
  std::unique_ptr<spectralize::RgbFromSpectral> to_rgb_;
  int source_channels_ = 0;
  // The current strip of converted rows, as floats.
  int strip_y0_ = 0, strip_y1_ = 0;
  std::vector<float> in_rows_, strip_;
};

bool SpectralInput::valid_file(const std::string& filename) const {
  // Cheap and strict: the extension, a small file, and a JSON object with a string "source".
  if (!Strutil::iends_with(filename, ".spectral")) return false;
  std::string text;
  if (!read_text(filename, text, 64 * 1024) || text.size() > 64 * 1024) return false;
  return spectralize::looks_like_recipe(text);
}

bool SpectralInput::open(const std::string& name, ImageSpec& newspec, const ImageSpec& config) {
  close();
  recipe_path_ = name;
  std::string text;
  if (!read_text(name, text, kMaxRecipeBytes)) {
    errorfmt("'{}': cannot read the recipe", name);
    return false;
  }
  if (text.size() > kMaxRecipeBytes) {
    errorfmt("'{}': too large for a recipe (over 1 MB)", name);
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
  if (t_opening.count(key)) {
    errorfmt("'{}': the recipe's source leads back to the recipe itself (a loop)", name);
    return false;
  }
  struct Guard {
    std::string key;
    ~Guard() { t_opening.erase(key); }
  } guard{key};
  t_opening.insert(key);

  try {
    spectralize::Recipe recipe = spectralize::parse_recipe(text, name, overrides);
    if (fs::weakly_canonical(fs::absolute(recipe.source), ec).string() == key) {
      errorfmt("'{}': the recipe's source is the recipe itself", name);
      return false;
    }
    if (!fs::exists(recipe.source, ec)) {
      errorfmt("'{}': source '{}' does not exist", name, recipe.source);
      return false;
    }
    source_ = ImageInput::open(recipe.source);
    if (!source_) {
      errorfmt("'{}': cannot read source '{}': {}", name, recipe.source, OIIO::geterror());
      return false;
    }
    const ImageSpec& src = source_->spec();
    source_channels_ = src.nchannels;
    auto log = [](int, const std::string&) {};  // the plugin has no console: errors only
    if (recipe.to_rgb) {
      const spectralize::ToRgbSettings& s = recipe.rgb;
      const auto layout = spectralize::analyse_spectral_layout(src, recipe.source);
      const auto spaces = spectralize::ColourSpaces::load(s.config);
      spectralize::RgbSettings rgb{spaces.resolve(s.colorspace), s.observer, s.illuminant};
      to_rgb_ = std::make_unique<spectralize::RgbFromSpectral>(layout, rgb, spaces);
      m_spec =
          spectralize::output_spec_like(src, to_rgb_->output_channels(), s.half, layout.alpha >= 0);
      m_spec.attribute("compression", s.compression);
      m_spec.attribute("spectralize:colorspace", rgb.colorspace);
      if (!layout.emissive) m_spec.attribute("spectralize:illuminant", s.illuminant);
    } else {
      job_ = recipe.spectral;
      job_.output = name;
      converter_ = std::make_unique<spectralize::SpectralConverter>(
          job_, src, source_->format_name(), log, report_);
      m_spec = converter_->output_spec();
      // Scanlines only: a reader presents the image; tiles are the writer's business.
      m_spec.tile_width = m_spec.tile_height = m_spec.tile_depth = 0;
    }
  } catch (const spectralize::Error& e) {
    errorfmt("{}", e.what());
    source_.reset();
    return false;
  } catch (const std::exception& e) {
    errorfmt("'{}': {}", name, e.what());
    source_.reset();
    return false;
  }
  newspec = m_spec;
  return true;
}

bool SpectralInput::close() {
  if (converter_) converter_->finish(report_, [](int, const std::string&) {});
  converter_.reset();
  to_rgb_.reset();
  if (source_) source_->close();
  source_.reset();
  strip_y0_ = strip_y1_ = 0;
  return true;
}

bool SpectralInput::fill_strip(int y) {
  const ImageSpec& src = source_->spec();
  const int row = y - src.y;
  strip_y0_ = src.y + (row / kStripRows) * kStripRows;
  strip_y1_ = std::min(strip_y0_ + kStripRows, src.y + src.height);
  const std::size_t n = static_cast<std::size_t>(src.width) * (strip_y1_ - strip_y0_);
  in_rows_.resize(n * source_channels_);
  if (!source_->read_scanlines(0, 0, strip_y0_, strip_y1_, 0, 0, source_channels_, TypeFloat,
                               in_rows_.data())) {
    errorfmt("'{}': cannot read its source: {}", recipe_path_, source_->geterror());
    strip_y0_ = strip_y1_ = 0;
    return false;
  }
  strip_.resize(n * m_spec.nchannels);
  try {
    if (converter_)
      converter_->convert(in_rows_.data(), n, strip_.data());
    else
      to_rgb_->convert(in_rows_.data(), source_channels_, n, strip_.data());
  } catch (const std::exception& e) {
    errorfmt("'{}': {}", recipe_path_, e.what());
    strip_y0_ = strip_y1_ = 0;
    return false;
  }
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
