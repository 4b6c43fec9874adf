// In place of pbrt-v4's RGBAlbedoSpectrum, RGBUnboundedSpectrum and RGBIlluminantSpectrum
// (pbrt/util/spectrum.h): one small type; the table it is fetched from says which kind it is.
// SampledWavelengths and SampledSpectrum stand for pbrt's (4 wavelengths, 4 values).
// Usage: pbrt_spectra REFLECTANCE.spztab EMISSION.spztab UNBOUNDED.spztab
#include <spectralize/rt.h>

#include <array>
#include <cstdio>

struct SampledWavelengths {
  std::array<float, 4> lambda;
};
struct SampledSpectrum {
  std::array<float, 4> v;
};

// pbrt's RGBColorSpace keeps its RGBToSpectrumTable; rt's tables go beside it, one per mode.
struct RtColorSpace {
  const spz_table* albedo;      // spectralize table --mode reflectance
  const spz_table* illuminant;  // spectralize table --mode emission
  const spz_table* unbounded;   // spectralize table --mode emission --emission-basis E
};

class RtSpectrum {
 public:
  RtSpectrum() = default;  // the zero spectrum: every value 0, MaxValue() 0
  RtSpectrum(const spz_table* table, const float rgb[3]) : status_(spz_fetch(table, rgb, &s_)) {}
  float operator()(float lambda) const { return spz_eval(&s_, lambda); }
  SampledSpectrum Sample(const SampledWavelengths& lambda) const {
    SampledSpectrum out;
    spz_eval4(&s_, lambda.lambda.data(), out.v.data());
    return out;
  }
  // pbrt's MaxValue() (light bounds, medium majorants): bounds every value operator() returns.
  float MaxValue() const { return spz_spectrum_max(&s_); }
  int Status() const { return status_; }  // SPZ_MAPPED: the RGB was outside the gamut

 private:
  spz_spectrum s_ = {};  // zero-initialised: the zero spectrum of no table
  int status_ = SPZ_INVALID;
};

// pbrt's CIE_Y_integral: what SpectrumToPhotometric() returns for an RGBIlluminantSpectrum
// (that of its colour space's normalised illuminant). Lights divide their scale by it; keep
// dividing rt's emission spectra by the same constant, never by their own luminance.
constexpr float kCieYIntegral = 106.856895f;

int main(int argc, char** argv) {
  if (argc != 4) return 2;
  char error[512];
  spz_table* tables[3];
  for (int i = 0; i < 3; ++i)
    if (!(tables[i] = spz_table_load(argv[i + 1], error, sizeof error))) {
      std::fprintf(stderr, "%s\n", error);
      return 1;
    }
  const RtColorSpace cs{tables[0], tables[1], tables[2]};
  const SampledWavelengths lambda{{430.0f, 510.0f, 580.0f, 640.0f}};

  // SpectrumImageTexture: pbrt filters the texture's RGB first (MIPMap::Filter<RGB>), then
  // RGBAlbedoSpectrum(*cs, Clamp(rgb, 0, 1)). With rt no clamp: out-of-gamut colours are mapped.
  const float texel[3] = {0.8f, 0.35f, 0.1f};
  const SampledSpectrum albedo = RtSpectrum(cs.albedo, texel).Sample(lambda);

  // DiffuseAreaLight "L" [r g b]: RGBIlluminantSpectrum(*cs, rgb) is scale * rsp(lambda) *
  // illuminant(lambda); rt's emission spectrum is the light's whole spectrum, any brightness.
  const float light_rgb[3] = {6.0f, 5.0f, 1.0f};
  const float scale = 1.0f / kCieYIntegral;  // the light's "scale" 1, normalised as pbrt does
  const SampledSpectrum emitted = RtSpectrum(cs.illuminant, light_rgb).Sample(lambda);

  // RGBUnboundedSpectrum (e.g. a medium's sigma_a): white (1, 1, 1) is the constant 1.
  const float white[3] = {1.0f, 1.0f, 1.0f};
  const SampledSpectrum flat = RtSpectrum(cs.unbounded, white).Sample(lambda);

  // A medium's majorant from MaxValue(); a default-constructed spectrum is zero everywhere.
  const RtSpectrum sigma_a(cs.unbounded, light_rgb), none;
  const SampledSpectrum absorbed = sigma_a.Sample(lambda), nothing = none.Sample(lambda);

  bool ok = none.MaxValue() == 0.0f;
  for (int i = 0; i < 4; ++i) {
    ok = ok && albedo.v[i] >= 0 && albedo.v[i] <= 1 && emitted.v[i] >= 0;
    ok = ok && absorbed.v[i] <= sigma_a.MaxValue() && nothing.v[i] == 0.0f;
    ok = ok && flat.v[i] > 0.999f && flat.v[i] < 1.001f;
    std::printf("%.0f nm: albedo %.4f, light %.4f, unbounded white %.4f\n", lambda.lambda[i],
                albedo.v[i], scale * emitted.v[i], flat.v[i]);
  }
  for (spz_table* t : tables) spz_table_free(t);
  std::printf("%s\n", ok ? "ok" : "FAILED");
  return ok ? 0 : 1;
}
