#include "pipeline/spectral_converter.h"

#include <Imath/half.h>
#include <OpenImageIO/parallel.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "imagefile/safe_output.h"

namespace spectralize {

void PixelCounts::add(const PixelCounts& o) {
  invalid += o.invalid;
  negative += o.negative;
  outside_locus += o.outside_locus;
  outside_solid += o.outside_solid;
  brighter_than_white += o.brighter_than_white;
  negative_component += o.negative_component;
  black += o.black;
  half_overflow += o.half_overflow;
  alpha_invalid += o.alpha_invalid;
  error_pixels += o.error_pixels;
  max_error = std::max(max_error, o.max_error);
  sum_error += o.sum_error;
}

SpectralConverter::SpectralConverter(Setup setup) : s_(std::move(setup)) {
  const Spectralizer& sp = s_.spectralizer;
  bands_ = sp.settings().grid.size();
  out_nch_ = s_.layout.spec().nchannels;
  for (const Xyz& c : sp.weights().columns()) {
    wx_.push_back(static_cast<float>(c.X));
    wy_.push_back(static_cast<float>(c.Y));
    wz_.push_back(static_cast<float>(c.Z));
  }
  const Xyz u = sp.unbalance();
  unbalance_[0] = static_cast<float>(u.X);
  unbalance_[1] = static_cast<float>(u.Y);
  unbalance_[2] = static_cast<float>(u.Z);
  white_y_ = sp.reference_white().Y;
}

PixelCounts SpectralConverter::counts() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return total_;
}

// The colours of pixels [b, b + m): straight RGB (grey replicated) into rgb, alpha into alpha
// (sanitised and counted), negative components counted.
void SpectralConverter::load_colours(const float* in, std::size_t b, std::size_t m, float* rgb,
                                     float* alpha, PixelCounts& c) const {
  const ChannelRoles& ch = s_.channels;
  for (std::size_t k = 0; k < m; ++k) {
    const float* px = in + (b + k) * s_.input_channels;
    float* v = rgb + k * 3;
    v[0] = px[ch.colour[0]];
    v[1] = ch.grey() ? v[0] : px[ch.colour[1]];
    v[2] = ch.grey() ? v[0] : px[ch.colour[2]];
    if (v[0] < 0 || v[1] < 0 || v[2] < 0) ++c.negative_component;
    alpha[k] = 1.0f;
    if (ch.alpha < 0) continue;
    float a = px[ch.alpha];
    if (!(a >= 0 && a <= 1)) {
      ++c.alpha_invalid;
      a = (std::isnan(a) || a < 0) ? 0.0f : 1.0f;
    }
    alpha[k] = a;
    // Associated colour is made straight, so the transfer function is undone on the colour.
    if (!s_.straight_alpha && a > 0 && a < 1)
      for (int i = 0; i < 3; ++i) v[i] /= a;
  }
}

// Counts a pixel by what the table did with it.
static void count_kind(Outcome kind, PixelCounts& c) {
  switch (kind) {
    case Outcome::invalid:
      ++c.invalid;
      break;
    case Outcome::negative:
      ++c.negative;
      break;
    case Outcome::outside_locus:
      ++c.outside_locus;
      break;
    case Outcome::outside_solid:
      ++c.outside_solid;
      break;
    case Outcome::black:
      ++c.black;
      break;
    case Outcome::exact:
      break;
  }
}

// One written pixel: bands scaled by `scale` (a reflectance's alpha) and rounded as the file
// stores them, alpha, the error measured on the written samples, and the preview's XYZ.
void SpectralConverter::finish_pixel(float* o, const PixelResult& r, float scale, float alpha,
                                     float* preview_xyz, PixelCounts& c) const {
  float* s = o + s_.layout.band_channel();
  if (scale != 1.0f)
    for (std::size_t i = 0; i < bands_; ++i) s[i] *= scale;
  if (s_.layout.alpha_channel() >= 0) o[s_.layout.alpha_channel()] = alpha;
  bool overflow = false;
  if (s_.half) {
    for (std::size_t i = 0; i < bands_; ++i) {
      if (s[i] > 65504.0f) s[i] = 65504.0f, overflow = true;
      s[i] = static_cast<float>(Imath::half(s[i]));
    }
  }
  c.half_overflow += overflow;
  float X = 0, Y = 0, Z = 0;
  for (std::size_t i = 0; i < bands_; ++i) {
    X += wx_[i] * s[i];
    Y += wy_[i] * s[i];
    Z += wz_[i] * s[i];
  }
  const Xyz target = static_cast<double>(scale) * r.target;
  if (target.max_abs() > 0) {
    const double err = relative_error(Xyz{X, Y, Z}, target);
    c.max_error = std::max(c.max_error, err);
    c.sum_error += err;
    ++c.error_pixels;
  }
  preview_xyz[0] = X * unbalance_[0];
  preview_xyz[1] = Y * unbalance_[1];
  preview_xyz[2] = Z * unbalance_[2];
}

void SpectralConverter::convert(const float* in, std::size_t n, float* out) {
  const bool reflectance = s_.spectralizer.settings().mode == Mode::reflectance;
  const bool has_alpha = s_.channels.alpha >= 0;
  const int band0 = s_.layout.band_channel(), preview0 = s_.layout.preview_channel();
  OIIO::parallel_for_chunked(
      0, static_cast<int64_t>(n), 1024,
      [&](int64_t begin, int64_t end) {
        ensure_signal_stack();  // OIIO's pool threads too: a crash here still cleans up
        PixelCounts c;
        const std::size_t b = static_cast<std::size_t>(begin),
                          m = static_cast<std::size_t>(end - begin);
        std::vector<float> rgb(m * 3), alpha(m), preview(m * 3);
        std::vector<Xyz> colours(m);
        std::vector<PixelResult> results(m);
        load_colours(in, b, m, rgb.data(), alpha.data(), c);
        s_.to_xyz.apply(rgb.data(), m);
        // Emission is linear: the spectrum of the premultiplied colour is alpha times the
        // straight one. A reflectance is bounded, so its straight colour is solved and the
        // spectrum multiplied by alpha. (Associated colour at alpha 0 is additive light: kept.)
        for (std::size_t k = 0; k < m; ++k) {
          Xyz x{rgb[k * 3], rgb[k * 3 + 1], rgb[k * 3 + 2]};
          const bool premultiply = has_alpha && (s_.straight_alpha || alpha[k] > 0);
          if (!reflectance && premultiply) x = static_cast<double>(alpha[k]) * x;
          // A NaN or infinite colour is invalid (the zero spectrum), never dimmed.
          if (reflectance && x.finite() && s_.spectralizer.target_of(x).Y > white_y_ * (1 + 1e-6))
            ++c.brighter_than_white;
          colours[k] = x;
        }
        float* first = out + b * out_nch_;
        s_.table.spectra(colours.data(), m, first + band0, results.data(),
                         static_cast<std::size_t>(out_nch_));
        for (std::size_t k = 0; k < m; ++k) {
          count_kind(results[k].kind, c);
          finish_pixel(first + k * out_nch_, results[k], reflectance ? alpha[k] : 1.0f, alpha[k],
                       &preview[k * 3], c);
        }
        if (preview0 >= 0) {
          s_.to_preview.apply(preview.data(), m);
          // Previews are written in the same sample type: keep them within HALF's range too.
          const float limit = s_.half ? 65504.0f : std::numeric_limits<float>::max();
          for (std::size_t k = 0; k < m; ++k)
            for (int i = 0; i < 3; ++i) {
              const float v = preview[k * 3 + i];
              first[k * out_nch_ + preview0 + i] =
                  std::isfinite(v) ? std::clamp(v, -limit, limit) : 0.0f;
            }
        }
        std::lock_guard<std::mutex> lock(mutex_);
        total_.add(c);
      },
      OIIO::paropt(s_.share ? s_.share->now() : s_.threads));
}

}  // namespace spectralize
