#include "pipeline/rgb_conversion.h"

#include <OpenImageIO/parallel.h>

#include <mutex>

#include "colour/colour_tags.h"
#include "imagefile/output_metadata.h"
#include "imagefile/safe_output.h"
#include "pipeline/rgb_from_spectral.h"
#include "spectralize/core/error.h"
#include "text/strings.h"

namespace spectralize {

struct RgbConversion::Parts {
  std::unique_ptr<RgbFromSpectral> to_rgb;
  OIIO::ImageSpec spec;
  OIIO::TypeDesc type;
  int in_nch = 0;
  int threads = 0;
  OptionNames names;
  std::mutex mutex;
  RgbCounts total;
};

RgbConversion::RgbConversion(const JobPlan& plan, const OIIO::ImageSpec& spec,
                             const std::string& output, const OutputFormat* format,
                             const LogFn& log)
    : parts_(std::make_unique<Parts>()) {
  if (!plan.decided() || !plan.to_rgb)
    throw Error("internal: an RGB conversion needs a plan decided for its spectral input");
  Parts& p = *parts_;
  const Settings& settings = plan.settings;
  const SpectralLayoutInfo& layout = plan.spectral;
  const ColourSpaces& spaces = plan.colour_spaces();
  const std::string& input = plan.input;
  ToRgbReport& rep = report_;
  auto warn = [&](const std::string& message) {
    rep.warnings.push_back(message);
    log(0, message);
  };
  p.names = plan.names;
  p.threads = settings.threads;
  p.in_nch = spec.nchannels;
  p.type = rgb_sample_type(settings);
  rep.input = input;
  rep.output = output;
  rep.output_format = format ? std::string(format->name) : std::string();
  rep.settings = settings;
  p.to_rgb = std::make_unique<RgbFromSpectral>(layout, settings, spaces);
  rep.colorspace = settings.display.empty()
                       ? settings.colorspace
                       : settings.display + " / " +
                             (settings.view.empty() ? std::string("default view") : settings.view);
  // The space written: the colour space, or the one a display's view ends in.
  const std::string written = settings.display.empty()
                                  ? settings.colorspace
                                  : spaces.display_colour_space(settings.display, settings.view);
  if (!written.empty()) rep.colorspace_identity = SpaceIdentity::of(spaces.facts(written));
  rep.kind = layout.emissive ? "emissive" : "reflective";
  rep.width = spec.width;
  rep.height = spec.height;
  rep.pixels = static_cast<std::uint64_t>(spec.width) * static_cast<std::uint64_t>(spec.height);
  rep.bands = static_cast<int>(layout.wavelengths.size());
  rep.first_nm = layout.wavelengths.front();
  rep.last_nm = layout.wavelengths.back();
  rep.polarised = layout.polarised;
  if (layout.polarised) log(1, "'" + input + "': polarised: S0 (intensity) used, S1..S3 ignored");
  if (!layout.unparsed.empty()) {
    std::string list;
    for (const std::string& n : layout.unparsed) list += (list.empty() ? "" : ", ") + n;
    warn("'" + input + "': channels " + clip(list, 300) +
         " look spectral but do not follow the layout's naming; ignored");
  }
  std::string date_warning;
  const std::string date_time = output_date_time(date_warning);
  if (!date_warning.empty() && format) warn(date_warning);
  p.spec = rgb_output_spec(spec, layout, settings, spaces, date_time);
  if (!format) return;  // a reader: nothing is written
  apply_compression(p.spec, *format, settings.compression);
  // The tags this format can hold (an ICC profile for TIFF, PNG, JPEG), or a warning.
  if (const std::string written = rgb_output_space(settings, spaces); !written.empty())
    for (const std::string& w :
         tag_colour_space(p.spec, spaces, written, rep.output_format, output))
      warn(w);
  else
    warn("'" + output + "': the OCIO view '" + settings.display + " / " + settings.view +
         "' names no colour space in the config; the file carries no colour tag");
  if (settings.integer_bits != 0 && settings.display.empty() &&
      spaces.is_linear(settings.colorspace))
    warn("'" + output + "': linear '" + settings.colorspace + "' in " +
         std::to_string(settings.integer_bits) + "-bit samples bands in the shadows; an encoded " +
         "space (" + p.names("colorspace") + " \"sRGB - Texture\") or " + p.names("display") +
         " suits integer files");
}

RgbConversion::~RgbConversion() = default;

const OIIO::ImageSpec& RgbConversion::output_spec() const {
  return parts_->spec;
}

int RgbConversion::input_channels() const {
  return parts_->in_nch;
}

int RgbConversion::output_channels() const {
  return parts_->to_rgb->output_channels();
}

void RgbConversion::convert(const float* in, std::size_t n, float* out) {
  Parts& p = *parts_;
  const int in_nch = p.in_nch, out_nch = p.to_rgb->output_channels();
  OIIO::parallel_for_chunked(
      0, static_cast<int64_t>(n), 4096,
      [&](int64_t b, int64_t e) {
        ensure_signal_stack();  // OIIO's pool threads too
        const RgbCounts c = p.to_rgb->convert(
            in + b * in_nch, in_nch, static_cast<std::size_t>(e - b), out + b * out_nch, p.type);
        std::lock_guard<std::mutex> lock(p.mutex);
        p.total.invalid += c.invalid;
        p.total.half_overflow += c.half_overflow;
        p.total.float_overflow += c.float_overflow;
        p.total.clipped += c.clipped;
      },
      OIIO::paropt(p.threads));
}

const ToRgbReport& RgbConversion::finish(const LogFn& log) {
  const RgbCounts& total = parts_->total;
  ToRgbReport& rep = report_;
  auto warn = [&](const std::string& message) {
    rep.warnings.push_back(message);
    log(0, message);
  };
  rep.invalid_pixels = total.invalid;
  rep.half_overflow_pixels = total.half_overflow;
  rep.float_overflow_pixels = total.float_overflow;
  rep.clipped_pixels = total.clipped;
  if (total.invalid > 0)
    warn("'" + rep.input + "': " + std::to_string(total.invalid) +
         " pixels have NaN or infinite samples, taken as 0");
  if (total.half_overflow > 0)
    warn("'" + rep.output + "': " + std::to_string(total.half_overflow) +
         " pixels exceed HALF's range (65504) and were clamped; use " + parts_->names("format") +
         " float to keep them");
  if (total.float_overflow > 0)
    warn("'" + rep.output + "': " + std::to_string(total.float_overflow) +
         " pixels exceed float's range (3.4e38) and were clamped to it; no sample type holds "
         "them (the spectra are brighter than float can integrate)");
  if (total.clipped > 0)
    warn("'" + rep.output + "': " + std::to_string(total.clipped) +
         " pixels have values outside 0..1 by more than half a code value, clipped by the "
         "integer format");
  return rep;
}

}  // namespace spectralize
