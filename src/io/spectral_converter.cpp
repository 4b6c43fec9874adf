#include "io/spectral_converter.h"

#include <Imath/half.h>
#include <OpenImageIO/parallel.h>
#include <OpenImageIO/strutil.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <limits>

#include "core/error.h"
#include "io/output_spec.h"
#include "io/spectral_layout.h"

namespace fs = std::filesystem;

namespace spectralize {

namespace {

// The primaries of the spaces the shipped config knows, to recognise EXR chromaticities.
struct KnownPrimaries {
  const char* space;
  float xy[8];  // red, green, blue, white
};
constexpr KnownPrimaries kKnownPrimaries[] = {
    {"Linear Rec.709 (sRGB)", {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f}},
    {"Linear Rec.2020", {0.708f, 0.292f, 0.170f, 0.797f, 0.131f, 0.046f, 0.3127f, 0.3290f}},
    {"Linear P3-D65", {0.680f, 0.320f, 0.265f, 0.690f, 0.150f, 0.060f, 0.3127f, 0.3290f}},
    {"ACEScg", {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f}},
    {"ACES2065-1", {0.7347f, 0.2653f, 0.0f, 1.0f, 0.0001f, -0.077f, 0.32168f, 0.33767f}},
};

// OCIO 2 colour interop IDs and the shipped config's names for them.
constexpr std::pair<const char*, const char*> kInteropIds[] = {
    {"lin_rec709_scene", "Linear Rec.709 (sRGB)"},
    {"lin_rec2020_scene", "Linear Rec.2020"},
    {"lin_p3d65_scene", "Linear P3-D65"},
    {"lin_ap1_scene", "ACEScg"},
    {"lin_ap0_scene", "ACES2065-1"},
    {"acescct_ap1", "ACEScct"},
    {"srgb_rec709_scene", "sRGB - Texture"},
    {"srgb_tx", "sRGB - Texture"},
    {"lin_ciexyzd65_scene", "CIE-XYZ-D65"},
    {"data", "Raw"}};

// Attributes of the input not carried over: they describe the input's encoding, not the image.
bool carried_over(const std::string& name) {
  static const char* const dropped_prefixes[] = {
      "oiio:", "openexr:", "exr:", "png:", "jpeg:", "tiff:", "hdr:", "rla:", "targa:", "bmp:"};
  static const char* const dropped[] = {"compression",    "Compression",
                                        "chromaticities", "ICCProfile",
                                        "planarconfig",   "Software",
                                        "DateTime",       "spectralLayoutVersion",
                                        "emissiveUnits",  "polarisationHandedness",
                                        "tile_width",     "tile_height"};
  for (const char* p : dropped_prefixes)
    if (name.rfind(p, 0) == 0) return false;
  for (const char* d : dropped)
    if (name == d) return false;
  return name.rfind("spectralize:", 0) != 0;
}

std::string now_exif() {
  std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y:%m:%d %H:%M:%S", std::localtime(&t));
  return buf;
}

// Chooses the input's colour space and says why.
std::pair<std::string, std::string> choose_colourspace(const ImageJobSettings& job,
                                                       const ColourSpaces& spaces,
                                                       const OIIO::ImageSpec& spec,
                                                       const LogFn& log) {
  if (!job.colorspace.empty()) return {spaces.resolve(job.colorspace), "--colorspace"};
  // EXR chromaticities are the most specific statement a file makes about its primaries.
  const OIIO::ParamValue* chroma =
      spec.find_attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8));
  if (chroma) {
    const float* c = static_cast<const float*>(chroma->data());
    for (const auto& known : kKnownPrimaries) {
      bool same = true;
      for (int i = 0; i < 8; ++i) same = same && std::abs(c[i] - known.xy[i]) < 2e-3f;
      if (same)
        return {spaces.resolve(known.space), std::string("EXR chromaticities of ") + known.space};
    }
    log(0, "'" + job.input +
               "': its EXR chromaticities match no known colour space; using the default for its "
               "data type (give --colorspace to choose)");
  }
  // The colour interop ID of OCIO 2 configs (e.g. "lin_ap1_scene"), if a writer set one.
  const std::string interop = spec.get_string_attribute("colorInteropID");
  for (const auto& [id, name] : kInteropIds)
    if (interop == id)
      return {spaces.resolve(name), "file metadata colorInteropID '" + interop + "'"};
  // OIIO reports "Linear" for every EXR and "sRGB" for every PNG without colour metadata: only a
  // name beyond those generic defaults is a statement about this file.
  const std::string meta = spec.get_string_attribute("oiio:ColorSpace");
  const bool generic =
      OIIO::Strutil::iequals(meta, "linear") || OIIO::Strutil::iequals(meta, "sRGB");
  if (!meta.empty() && !generic) {
    try {
      return {spaces.resolve(meta), "file metadata oiio:ColorSpace '" + meta + "'"};
    } catch (const Error&) {
      log(0, "'" + job.input + "': its colour space '" + meta +
                 "' is not in the OCIO config; using the default for its data type");
    }
  }
  if (spec.format.is_floating_point())
    return {spaces.resolve(kDefaultColourSpace), "default for floating-point data"};
  return {spaces.resolve("sRGB - Texture"), "default for integer data"};
}

}  // namespace

// Per-strip counters, summed under a lock at the end of each parallel chunk.
struct SpectralConverter::Counters {
  std::uint64_t invalid = 0, negative = 0, outside_locus = 0, outside_solid = 0, black = 0,
                negative_component = 0, half_overflow = 0, error_pixels = 0;
  double max_error = 0, sum_error = 0;
  void add(const Counters& o) {
    invalid += o.invalid;
    negative += o.negative;
    outside_locus += o.outside_locus;
    outside_solid += o.outside_solid;
    black += o.black;
    negative_component += o.negative_component;
    half_overflow += o.half_overflow;
    error_pixels += o.error_pixels;
    max_error = std::max(max_error, o.max_error);
    sum_error += o.sum_error;
  }
};

SpectralConverter::SpectralConverter(const ImageJobSettings& job, const OIIO::ImageSpec& spec,
                                     const std::string& input_format, const LogFn& log,
                                     ImageReport& rep)
    : job_(job), total_(std::make_unique<Counters>()) {
  rep.input_format = input_format;
  rep.width = spec.width;
  rep.height = spec.height;
  rep.input_channels = spec.nchannels;
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    throw Error("'" + job.input + "': empty image (" + std::to_string(spec.width) + "x" +
                std::to_string(spec.height) + ", " + std::to_string(spec.nchannels) + " channels)");
  if (spec.depth > 1) throw Error("'" + job.input + "': volume images are not supported");

  // Which channels are colour and which is alpha: grey (1 or grey + alpha), RGB, RGBA, ...
  const int nch = spec.nchannels;
  in_nch_ = nch;
  int alpha = spec.alpha_channel;
  if (alpha < 0 && nch == 2) alpha = 1;
  if (alpha < 0 && nch >= 4 && spec.channel_name(3) == "A") alpha = 3;
  grey_ = nch < 3 || (nch == 2 && alpha == 1);
  if (!grey_ && alpha >= 0 && alpha < 3) alpha = -1;  // an "alpha" among R, G, B: colour
  alpha_ = alpha;
  rep.alpha = alpha >= 0;
  // Colour space and mode, with reasons.
  ColourSpaces spaces = ColourSpaces::load(job.config);
  auto [space, space_reason] = choose_colourspace(job, spaces, spec, log);
  rep.colorspace = space;
  rep.colorspace_reason = space_reason;
  const bool float_data = spec.format.is_floating_point();
  SpectralizerSettings settings = job.spectral;
  if (job.mode == "auto") {
    settings.mode = float_data ? Mode::emission : Mode::reflectance;
    rep.mode_reason = float_data ? "auto: floating-point data is light (emission)"
                                 : "auto: integer data is a texture (reflectance)";
  } else {
    settings.mode = parse_mode(job.mode);
    rep.mode_reason = "--mode";
  }
  rep.mode = std::string(to_string(settings.mode));
  log(1, "'" + job.input + "': " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
             ", " + std::to_string(nch) + " channels, " + spec.format.c_str() + " (" +
             rep.input_format + "); colour space '" + space + "' (" + space_reason + "); mode " +
             rep.mode + " (" + rep.mode_reason + ")");

  to_xyz_ = std::make_unique<ColourTransform>(spaces.to_xyz(space));
  to_preview_ = std::make_unique<ColourTransform>(spaces.from_xyz(kDefaultColourSpace));
  spectralizer_ = std::make_unique<Spectralizer>(settings);
  table_ = std::make_unique<SpectralTable>(*spectralizer_, job.method);
  const Spectralizer& spectralizer = *spectralizer_;
  SpectralTable& table = *table_;
  const std::size_t bands = settings.grid.size();
  bands_ = bands;
  rep.bands = static_cast<int>(bands);
  rep.wavelengths = settings.grid.to_string();
  rep.observer = spectralizer.observer().name;
  rep.illuminant = spectralizer.illuminant() ? spectralizer.illuminant()->name : "";
  rep.filter = settings.model == Model::paper ? settings.filter.to_string() : "";
  rep.model = std::string(to_string(settings.model));
  rep.emission_basis = settings.mode == Mode::emission ? settings.emission_basis : "";
  rep.method = job.method == SpectralTable::Method::table ? "table" : "exact";
  rep.sample_format = job.half ? "half" : "float";
  rep.compression = job.compression;

  // The persistent node cache, keyed by everything the nodes depend on.
  if (!job.cache_dir.empty() && job.method == SpectralTable::Method::table) {
    std::error_code ec;
    fs::create_directories(job.cache_dir, ec);
    if (!fs::is_directory(job.cache_dir))
      throw Error("--cache '" + job.cache_dir + "': cannot create the folder");
    const std::uint64_t h = std::hash<std::string>{}(table.cache_key());
    char name[64];
    std::snprintf(name, sizeof name, "spectralize-table-%016llx.bin",
                  static_cast<unsigned long long>(h));
    rep.cache_file = (fs::path(job.cache_dir) / name).string();
    cache_file_ = rep.cache_file;
    std::string why = table.load(rep.cache_file);
    if (!why.empty()) {
      rep.cache_status = "rebuilt: " + why;
      log(0, "cache '" + rep.cache_file + "' ignored and rebuilt: " + why);
    } else {
      rep.cache_status = table.stats().nodes_loaded > 0 ? "loaded" : "new";
    }
    log(2, "cache '" + rep.cache_file + "': " + rep.cache_status + ", " +
               std::to_string(table.stats().nodes_loaded) + " nodes");
  }

  // The output: R, G, B preview (the spectra integrated back), alpha, then one channel per band.
  preview_ = 3 + (rep.alpha ? 1 : 0);
  out_nch_ = preview_ + static_cast<int>(bands);
  OIIO::ImageSpec& ospec = out_spec_;
  ospec = output_spec_like(spec, out_nch_, job.half, rep.alpha);
  const auto kind = settings.mode == Mode::emission ? SpectralChannel::Kind::emissive
                                                    : SpectralChannel::Kind::reflective;
  for (std::size_t i = 0; i < bands; ++i)
    ospec.channelnames.push_back(spectral_channel_name(kind, settings.grid[i]));
  for (const auto& p : spec.extra_attribs)
    if (carried_over(p.name().string())) ospec.extra_attribs.push_back(p);
  ospec.attribute("compression", job.compression);
  if (job.tile > 0) {
    ospec.tile_width = job.tile;
    ospec.tile_height = job.tile;
  }
  ospec.attribute(kLayoutVersionAttr, kLayoutVersion);
  if (settings.mode == Mode::emission) ospec.attribute(kEmissiveUnitsAttr, kEmissiveUnits);
  ospec.attribute("Software", "spectralize " SPECTRALIZE_VERSION);
  ospec.attribute("DateTime", job.date_time.empty() ? now_exif() : job.date_time);
  ospec.attribute("spectralize:version", SPECTRALIZE_VERSION);
  ospec.attribute("spectralize:mode", rep.mode);
  ospec.attribute("spectralize:wavelengths", rep.wavelengths);
  ospec.attribute("spectralize:observer", rep.observer);
  if (!rep.illuminant.empty()) ospec.attribute("spectralize:illuminant", rep.illuminant);
  if (!rep.filter.empty()) ospec.attribute("spectralize:filter", rep.filter);
  ospec.attribute("spectralize:model", rep.model);
  if (!rep.emission_basis.empty()) ospec.attribute("spectralize:emissionBasis", rep.emission_basis);
  ospec.attribute("spectralize:method", rep.method);
  ospec.attribute("spectralize:colorspace", rep.colorspace);
  ospec.attribute("spectralize:previewColorSpace", std::string(kDefaultColourSpace));

  // Weights for measuring the written samples, and the white balance to undo for previews.
  wx_.resize(bands);
  wy_.resize(bands);
  wz_.resize(bands);
  for (std::size_t i = 0; i < bands; ++i) {
    const Xyz& c = spectralizer.weights().columns()[i];
    wx_[i] = static_cast<float>(c.X);
    wy_[i] = static_cast<float>(c.Y);
    wz_[i] = static_cast<float>(c.Z);
  }
  const Xyz white = spectralizer.reference_white();
  unbalance_[0] = static_cast<float>(kWhiteD65.X / white.X);
  unbalance_[1] = static_cast<float>(kWhiteD65.Y / white.Y);
  unbalance_[2] = static_cast<float>(kWhiteD65.Z / white.Z);
}

void SpectralConverter::convert(const float* in, std::size_t n, float* out) {
  const int nch = in_nch_, out_nch = out_nch_;
  OIIO::parallel_for_chunked(
      0, static_cast<int64_t>(n), 1024,
      [&](int64_t begin, int64_t end) {
        Counters c;
        const std::size_t b = static_cast<std::size_t>(begin), e = static_cast<std::size_t>(end);
        const std::size_t m = e - b;
        std::vector<float> xyz(m * 3), preview(m * 3);
        std::vector<Xyz> colours(m);
        std::vector<PixelResult> results(m);
        // Colour: RGB (grey replicated) to XYZ by OCIO.
        for (std::size_t k = 0; k < m; ++k) {
          const float* px = in + (b + k) * nch;
          float* v = &xyz[k * 3];
          v[0] = px[0];
          v[1] = grey_ ? px[0] : px[1];
          v[2] = grey_ ? px[0] : px[2];
          if (v[0] < 0 || v[1] < 0 || v[2] < 0) ++c.negative_component;
        }
        to_xyz_->apply(xyz.data(), m);
        for (std::size_t k = 0; k < m; ++k)
          colours[k] = {xyz[k * 3], xyz[k * 3 + 1], xyz[k * 3 + 2]};
        // Spectra straight into the output rows, after the preview (and alpha) channels.
        float* first = out + b * out_nch;
        table_->spectra(colours.data(), m, first + preview_, results.data(),
                        static_cast<std::size_t>(out_nch));
        for (std::size_t k = 0; k < m; ++k) {
          float* o = first + k * out_nch;
          float* s = o + preview_;
          const PixelResult& r = results[k];
          switch (r.kind) {
            case PixelKind::invalid:
              ++c.invalid;
              break;
            case PixelKind::negative:
              ++c.negative;
              break;
            case PixelKind::outside_locus:
              ++c.outside_locus;
              break;
            case PixelKind::outside_solid:
              ++c.outside_solid;
              break;
            case PixelKind::black:
              ++c.black;
              break;
            case PixelKind::in_gamut:
              break;
          }
          if (alpha_ >= 0) o[3] = in[(b + k) * nch + alpha_];
          // Samples as the file will hold them (HALF rounding, clamped to HALF's range).
          bool overflow = false;
          if (job_.half) {
            for (std::size_t i = 0; i < bands_; ++i) {
              if (s[i] > 65504.0f) s[i] = 65504.0f, overflow = true;
              s[i] = static_cast<float>(Imath::half(s[i]));
            }
          }
          c.half_overflow += overflow;
          // Their XYZ: the error measured on the written data, and the preview.
          float X = 0, Y = 0, Z = 0;
          for (std::size_t i = 0; i < bands_; ++i) {
            X += wx_[i] * s[i];
            Y += wy_[i] * s[i];
            Z += wz_[i] * s[i];
          }
          if (r.target.max_abs() > 0) {
            const double err = relative_error(Xyz{X, Y, Z}, r.target);
            c.max_error = std::max(c.max_error, err);
            c.sum_error += err;
            ++c.error_pixels;
          }
          float* q = &preview[k * 3];
          q[0] = X * unbalance_[0];
          q[1] = Y * unbalance_[1];
          q[2] = Z * unbalance_[2];
        }
        to_preview_->apply(preview.data(), m);
        // The preview is written in the same sample type: keep it within HALF's range too
        // (a clamped pixel is already counted as a HALF overflow).
        const float limit = job_.half ? 65504.0f : std::numeric_limits<float>::max();
        for (std::size_t k = 0; k < m; ++k)
          for (int ch = 0; ch < 3; ++ch)
            first[k * out_nch + ch] = std::clamp(preview[k * 3 + ch], -limit, limit);
        std::lock_guard<std::mutex> lock(mutex_);
        total_->add(c);
      },
      OIIO::paropt(job_.threads));
}

SpectralConverter::~SpectralConverter() = default;

void SpectralConverter::finish(ImageReport& rep, const LogFn& log) {
  const Counters& total = *total_;
  rep.invalid_pixels = total.invalid;
  rep.negative_pixels = total.negative;
  rep.outside_locus_pixels = total.outside_locus;
  rep.outside_solid_pixels = total.outside_solid;
  rep.black_pixels = total.black;
  rep.negative_component_pixels = total.negative_component;
  rep.half_overflow_pixels = total.half_overflow;
  rep.error_pixels = total.error_pixels;
  rep.max_relative_xyz_error = total.max_error;
  rep.mean_relative_xyz_error = total.error_pixels ? total.sum_error / total.error_pixels : 0.0;
  rep.cache = table_->stats();
  // Persist the nodes for the next run.
  if (!cache_file_.empty() && table_->dirty()) {
    std::string why = table_->save(cache_file_);
    if (!why.empty()) log(0, "cache '" + cache_file_ + "' not saved: " + why);
  }
}

}  // namespace spectralize
