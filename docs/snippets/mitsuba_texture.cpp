// In place of Mitsuba 3's srgb_model_fetch / srgb_model_eval (mitsuba/render/srgb.h) in its
// bitmap texture and environment emitter (spectral variants). Mitsuba stores each texel's
// sigmoid coefficients and, filtering bilinearly, evaluates the spectra of the four texels and
// blends the spectra. With rt the texels stay linear RGB (as the rgb variants store them): the
// RGB is filtered and the filtered colour fetched once, whose spectrum is exact for that colour
// (blending the four texels' rt spectra would give the same colour at four fetches).
// Usage: mitsuba_texture REFLECTANCE.spztab EMISSION.spztab
#include <spectralize/rt.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

using Wavelength = std::array<float, 4>;  // si.wavelengths
using Spectrum = std::array<float, 4>;    // UnpolarizedSpectrum

class RtBitmap {
 public:
  RtBitmap(const spz_table* table, int width, int height, std::vector<float> rgb)
      : table_(table), w_(width), h_(height), rgb_(std::move(rgb)) {
    double m[9];
    spz_table_rgb_to_xyz(table, m);
    for (int c = 0; c < 3; ++c) y_[c] = m[3 + c];  // the luminance row of RGB -> XYZ
  }

  // Texture::eval(si): bilinear RGB at (u, v), then the spectrum at 4 wavelengths in one call
  // (spz_fetch then spz_eval4, bit for bit).
  Spectrum eval(float u, float v, const Wavelength& lambda, float scale = 1.0f) const {
    float rgb[3];
    bilinear(u, v, rgb);
    Spectrum out;
    spz_fetch_eval4(table_, rgb, lambda.data(), out.data(), nullptr);
    for (float& x : out) x *= scale;  // an emitter's "scale"; no D65 factor: it is the light's
    return out;
  }

  // What srgb_model_mean() served (texture means, the envmap's sampling distribution): the
  // texel's luminance. rt's spectrum has exactly the RGB's colour, so Y needs no integral.
  float luminance(int x, int y) const {
    const float* c = &rgb_[3 * static_cast<std::size_t>(y * w_ + x)];
    return static_cast<float>(y_[0] * c[0] + y_[1] * c[1] + y_[2] * c[2]);
  }

 private:
  void bilinear(float u, float v, float out[3]) const {
    const float x = u * w_ - 0.5f, y = v * h_ - 0.5f;
    const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
    const float fx = x - x0, fy = y - y0;
    auto at = [&](int xi, int yi, int c) {  // clamp wrap mode
      xi = xi < 0 ? 0 : (xi >= w_ ? w_ - 1 : xi);
      yi = yi < 0 ? 0 : (yi >= h_ ? h_ - 1 : yi);
      return rgb_[3 * static_cast<std::size_t>(yi * w_ + xi) + c];
    };
    for (int c = 0; c < 3; ++c)
      out[c] = (1 - fy) * ((1 - fx) * at(x0, y0, c) + fx * at(x0 + 1, y0, c)) +
               fy * ((1 - fx) * at(x0, y0 + 1, c) + fx * at(x0 + 1, y0 + 1, c));
  }

  const spz_table* table_;
  int w_, h_;
  std::vector<float> rgb_;
  double y_[3];
};

int main(int argc, char** argv) {
  if (argc != 3) return 2;
  char error[512];
  spz_table* reflectance = spz_table_load(argv[1], error, sizeof error);
  spz_table* emission = reflectance ? spz_table_load(argv[2], error, sizeof error) : nullptr;
  if (!emission) {
    std::fprintf(stderr, "%s\n", error);
    spz_table_free(reflectance);
    return 1;
  }
  // A 2 x 2 texture: red, green / blue, white. Its centre filters to the mean of the four.
  const RtBitmap albedo(reflectance, 2, 2,
                        {0.7f, 0.1f, 0.1f, 0.1f, 0.6f, 0.1f,  //
                         0.1f, 0.1f, 0.8f, 0.9f, 0.9f, 0.9f});
  const RtBitmap sky(emission, 2, 2,
                     {4.0f, 3.5f, 3.0f, 0.2f, 0.3f, 0.6f,  //
                      0.5f, 0.6f, 0.9f, 900.0f, 800.0f, 500.0f});
  const Wavelength lambda{450.0f, 520.0f, 590.0f, 660.0f};
  const Spectrum rho = albedo.eval(0.5f, 0.5f, lambda);
  const Spectrum sun = sky.eval(0.75f, 0.75f, lambda, 2.0f);
  bool ok = sky.luminance(1, 1) > 500.0f;
  for (int i = 0; i < 4; ++i) {
    ok = ok && rho[i] >= 0 && rho[i] <= 1 && sun[i] > 0;
    std::printf("%.0f nm: albedo %.4f, sun %.1f\n", lambda[i], rho[i], sun[i]);
  }
  spz_table_free(reflectance);
  spz_table_free(emission);
  std::printf("%s\n", ok ? "ok" : "FAILED");
  return ok ? 0 : 1;
}
