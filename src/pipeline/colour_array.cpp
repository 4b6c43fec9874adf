#include "pipeline/colour_array.h"

#include <OpenImageIO/parallel.h>

#include "classify/input_interpretation.h"
#include "imagefile/safe_output.h"
#include "pipeline/render_table.h"
#include "pipeline/spectral_image_layout.h"
#include "spectralize/core/error.h"

namespace spectralize {

ColourArrays::ColourArrays(const JobPlan& plan, TablePool& pool, const LogFn& log)
    : settings_(plan.settings), warnings_(plan.warnings), spaces_(plan.spaces) {
  settings_.half = false;
  to_xyz_ = spaces_->to_xyz(settings_.colorspace);
  entry_ =
      &pool.get(settings_, table_frame(*spaces_, settings_.colorspace), log, plan.names("cache"));
}

PixelCounts ColourArrays::spectra(const float* rgb, std::size_t n, float* out) const {
  // The image kernel on a bare layout: one "pixel" per colour, no alpha, no previews.
  const auto layout = bare_spectra_layout(settings_.spectral);
  SpectralConverter converter(SpectralConverter::Setup{
      *entry_->spectralizer, *entry_->table, ChannelRoles{{0, 1, 2}, -1, {}}, 3, false, to_xyz_,
      to_xyz_, *layout, false, settings_.threads});
  converter.convert(rgb, n, out);
  return converter.counts();
}

RgbCounts rgb_of_spectra(const float* spectra, std::size_t n,
                         const std::vector<double>& wavelengths, const JobPlan& plan, float* rgb,
                         const std::string& where) {
  const ColourSpaces& spaces = plan.colour_spaces();
  const Settings& s = plan.settings;
  const SpectralLayoutInfo layout =
      spectral_layout_of_samples(wavelengths, s.spectral.mode == Mode::emission, where);
  const RgbFromSpectral integrate(layout, s, spaces);
  const int bands = static_cast<int>(wavelengths.size());
  RgbCounts total;
  std::mutex mutex;
  OIIO::parallel_for_chunked(
      0, static_cast<int64_t>(n), 4096,
      [&](int64_t begin, int64_t end) {
        ensure_signal_stack();  // OIIO's pool threads too
        const auto b = static_cast<std::size_t>(begin);
        const RgbCounts c =
            integrate.convert(spectra + b * bands, bands, static_cast<std::size_t>(end - begin),
                              rgb + b * 3, OIIO::TypeFloat);
        std::lock_guard<std::mutex> lock(mutex);
        total.invalid += c.invalid;
        total.half_overflow += c.half_overflow;
        total.float_overflow += c.float_overflow;
        total.clipped += c.clipped;
      },
      OIIO::paropt(s.threads));
  return total;
}

}  // namespace spectralize
