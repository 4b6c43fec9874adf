// The streamed image jobs (pipeline/image_job.h) on small images written here, through their
// public functions only: the bands of the spectral OpenEXR integrate back to the input colour
// (emission: its XYZ; reflectance: its XYZ white-balanced to the reference illuminant, and
// within [0, 1]; docs/DESIGN.md §3) and its previews are the input again; bad pixels are
// written as zero spectra, counted in the report and recorded in the header; run_to_rgb_job
// gives the input back; an output that is the input under any name is refused; a throw before
// the commit leaves nothing behind. Oracles: the reference integration and the Rec.709 matrix
// of tests/unit/test_support.h, the sRGB curve written here, and the pixels each case writes.

#include "pipeline/image_job.h"

#include "pipeline/job_plan.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "file_test_support.h"
#include "spectralize/core/error.h"
#include "test_support.h"

namespace fs = std::filesystem;

namespace spectralize {
namespace {

const std::string kRec709 = "Linear Rec.709 (sRGB)";
const std::string kSrgbTexture = "sRGB - Texture";

// Float samples and OCIO's float maths (docs/DESIGN.md §3: float files, 1e-5).
constexpr double kFloatTolerance = 1e-5;
// A colour through OCIO's float matrices twice (the previews, a round trip back to RGB).
constexpr double kTwiceThroughOcio = 1e-4;

struct TempDir : test::TempDir {
  TempDir() : test::TempDir("image_job") {}
};

// The settings of a job on an input in `space`, float samples (the 1e-5 bar).
Settings settings_for(ModeChoice mode, const std::string& space) {
  Settings s;
  s.colorspace = space;
  s.preview_colorspace = kRec709;
  s.mode = mode;
  s.half = false;
  s.threads = 2;
  return s;
}

const LogFn kQuiet = [](int, const std::string&) {};

// The jobs as a front end runs them: planned (pipeline/job_plan.h), then run. To RGB keeps the
// settings' sample type and compression as given.
const ImageJobOptions kNoOptions;  // a named default: GCC 12 warns of a temporary's std::function
ImageReport run_image_job(const std::string& in, const std::string& out, const Settings& s,
                          const ProgressFn& progress, const LogFn& log,
                          const ImageJobOptions& options = kNoOptions) {
  return spectralize::run_image_job(plan_to_spectral(s, out, OptionNames{"--", "-o"}), in, out,
                                    progress, log, options);
}
ToRgbReport run_to_rgb_job(const std::string& in, const std::string& out, const Settings& s,
                           const ProgressFn& progress, const LogFn& log,
                           const std::function<void(const ToRgbReport&)>& before_commit = {}) {
  return spectralize::run_to_rgb_job(plan_to_rgb(s, out, true, true, OptionNames{"--", "-o"}), in,
                                     out, progress, log, before_commit);
}

// An RGB image of w x h pixels, `px` interleaved, written by OIIO in `type` samples.
void write_rgb(const std::string& path, int w, int h, OIIO::TypeDesc type,
               const std::vector<float>& px) {
  ASSERT_EQ(px.size(), static_cast<std::size_t>(w) * h * 3);
  const OIIO::ImageSpec spec(w, h, 3, type);
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out && out->open(path, spec)) << OIIO::geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeFloat, px.data())) << out->geterror();
  ASSERT_TRUE(out->close());
}

// Every channel of a file, as float, read by OIIO.
struct Image {
  OIIO::ImageSpec spec;
  std::vector<float> px;
  float at(int pixel, int channel) const {
    return px[static_cast<std::size_t>(pixel) * spec.nchannels + channel];
  }
  int channel(const std::string& name) const { return spec.channelindex(name); }
  int pixels() const { return spec.width * spec.height; }
};
Image read_image(const std::string& path) {
  Image im;
  auto in = OIIO::ImageInput::open(path);
  EXPECT_TRUE(in) << OIIO::geterror();
  if (!in) return im;
  im.spec = in->spec();
  im.px.resize(static_cast<std::size_t>(im.spec.width) * im.spec.height * im.spec.nchannels);
  EXPECT_TRUE(in->read_image(0, 0, 0, im.spec.nchannels, OIIO::TypeFloat, im.px.data()));
  return im;
}

// The spectral channels <prefix><nm>nm ("S0.550,000000nm", a decimal comma), in the file's
// order, with their wavelengths; and the grid they lie on (checked even).
struct Bands {
  std::vector<int> channels;
  std::vector<double> nm;
  WavelengthGrid grid() const {
    EXPECT_GE(nm.size(), 2u);
    const WavelengthGrid g(nm.front(), nm.back(), nm[1] - nm[0]);
    EXPECT_EQ(g.size(), nm.size());
    for (std::size_t i = 0; i < std::min(g.size(), nm.size()); ++i) EXPECT_NEAR(g[i], nm[i], 1e-9);
    return g;
  }
};
Bands bands_of(const OIIO::ImageSpec& spec, const std::string& prefix) {
  Bands b;
  for (int c = 0; c < spec.nchannels; ++c) {
    const std::string& name = spec.channelnames[c];
    if (name.rfind(prefix, 0) != 0 || name.size() < prefix.size() + 3 ||
        name.substr(name.size() - 2) != "nm")
      continue;
    std::string number = name.substr(prefix.size(), name.size() - prefix.size() - 2);
    std::replace(number.begin(), number.end(), ',', '.');
    b.channels.push_back(c);
    b.nm.push_back(std::stod(number));
  }
  return b;
}

std::vector<double> spectrum(const Image& im, const Bands& b, int pixel) {
  std::vector<double> v;
  for (int c : b.channels) v.push_back(im.at(pixel, c));
  return v;
}

// The XYZ of a spectrum by the reference integration: emission, or reflectance under the
// reference illuminant (rho == 1 at Y = 1).
Xyz integrated(const WavelengthGrid& grid, const std::vector<double>& values,
               const std::string& illuminant = "") {
  const Observer& obs = Observer::get("cie1931");
  if (illuminant.empty()) return test::reference_xyz(grid, values, obs, nullptr);
  const Illuminant e = Illuminant::get(illuminant);
  return test::reference_xyz(grid, values, obs, &e.spd);
}

// The white balance of a reflectance: the reference white (rho == 1) over the D65 white.
Xyz balance(const WavelengthGrid& grid, const std::string& illuminant) {
  const Xyz w = integrated(grid, std::vector<double>(grid.size(), 1.0), illuminant);
  const Xyz d65 = test::d65_white();
  return {w.X / d65.X, w.Y / d65.Y, w.Z / d65.Z};
}

// The sRGB decoding curve (IEC 61966-2-1).
double srgb_decode(double v) {
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

std::string bytes_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::set<std::string> names_in(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
  return names;
}

// Linear Rec.709 colours inside the gamut (so inside the locus), dark to brighter than white.
const std::vector<std::array<float, 3>> kLights = {
    {1, 1, 1},    {0.18f, 0.18f, 0.18f}, {0.8f, 0.2f, 0.1f}, {0.05f, 0.6f, 0.3f},
    {40, 30, 20}, {0.3f, 0.3f, 0.9f},    {2, 0.5f, 0.25f},   {0.01f, 0.02f, 0.03f},
};

std::vector<float> interleaved(const std::vector<std::array<float, 3>>& colours) {
  std::vector<float> px;
  for (const auto& c : colours) px.insert(px.end(), c.begin(), c.end());
  return px;
}

// --- RGB to spectral ---

TEST(ImageJob, EmissionBandsIntegrateBackToTheInputColour) {
  TempDir t;
  const std::string in = t / "light.exr", out = t / "light_spectral.exr";
  write_rgb(in, 4, 2, OIIO::TypeFloat, interleaved(kLights));
  const ImageReport rep =
      run_image_job(in, out, settings_for(ModeChoice::emission, kRec709), {}, kQuiet);
  const Image e = read_image(out);
  ASSERT_EQ(e.pixels(), 8);
  EXPECT_EQ(e.spec.format, OIIO::TypeFloat);
  EXPECT_EQ(e.spec.get_string_attribute("spectralize:mode"), "emission");
  const Bands b = bands_of(e.spec, "S0.");
  ASSERT_EQ(b.nm.size(), 81u);  // the default grid, 380:780:5
  const WavelengthGrid grid = b.grid();
  for (int p = 0; p < 8; ++p) {
    SCOPED_TRACE(p);
    const auto& c = kLights[p];
    const std::vector<double> s = spectrum(e, b, p);
    EXPECT_LT(test::rel_err(integrated(grid, s), test::rgb(test::kRec709ToXyz, c[0], c[1], c[2])),
              kFloatTolerance);
    EXPECT_GE(*std::min_element(s.begin(), s.end()), 0.0);  // light is never negative
    // The previews are the spectrum's colour in Linear Rec.709: the input again.
    const float peak = std::max({c[0], c[1], c[2]});
    for (int k = 0; k < 3; ++k)
      EXPECT_LT(std::abs(e.at(p, e.channel(std::string(1, "RGB"[k]))) - c[k]) / peak,
                kTwiceThroughOcio);
  }
  EXPECT_EQ(rep.width, 4);
  EXPECT_EQ(rep.height, 2);
  EXPECT_EQ(rep.pixels, 8u);
  EXPECT_EQ(rep.bands, 81);
  EXPECT_EQ(rep.settings.spectral.mode, Mode::emission);
  EXPECT_EQ(rep.colorspace, kRec709);
  EXPECT_EQ(rep.out_of_gamut_pixels(), 0u);
  EXPECT_LT(rep.counts.max_error, kFloatTolerance);
}

TEST(ImageJob, AnSrgbPngIsABoundedReflectanceOfItsBalancedColour) {
  TempDir t;
  const std::string in = t / "paint.png", out = t / "paint.exr";
  // 8-bit codes (OIIO reads them as code / 255); no white at 255, which is the solid's edge.
  const std::vector<std::array<int, 3>> codes = {{245, 245, 245}, {128, 128, 128}, {200, 80, 40},
                                                 {30, 150, 60},   {10, 10, 90},    {0, 0, 0}};
  std::vector<float> px;
  for (const auto& c : codes)
    for (int v : c) px.push_back(static_cast<float>(v) / 255.0f);
  write_rgb(in, 3, 2, OIIO::TypeUInt8, px);
  const ImageReport rep =
      run_image_job(in, out, settings_for(ModeChoice::reflectance, kSrgbTexture), {}, kQuiet);
  const Image e = read_image(out);
  ASSERT_EQ(e.pixels(), 6);
  EXPECT_EQ(e.spec.get_string_attribute("spectralize:mode"), "reflectance");
  const Bands b = bands_of(e.spec, "T.");
  ASSERT_EQ(b.nm.size(), 81u);
  const WavelengthGrid grid = b.grid();
  const Xyz white = balance(grid, "D65");
  for (int p = 0; p < 6; ++p) {
    SCOPED_TRACE(p);
    const std::vector<double> s = spectrum(e, b, p);
    EXPECT_GE(*std::min_element(s.begin(), s.end()), 0.0);
    EXPECT_LE(*std::max_element(s.begin(), s.end()), 1.0 + 1e-6);  // float rounding at 1
    const auto& c = codes[p];
    if (c[0] + c[1] + c[2] == 0) {
      EXPECT_EQ(*std::max_element(s.begin(), s.end()), 0.0);  // black: no light reflected
      continue;
    }
    const Xyz lin = test::rgb(test::kRec709ToXyz, srgb_decode(c[0] / 255.0),
                              srgb_decode(c[1] / 255.0), srgb_decode(c[2] / 255.0));
    const Xyz want{lin.X * white.X, lin.Y * white.Y, lin.Z * white.Z};
    // 1e-5, with room for OCIO's sRGB curve (4e-7 from the textbook one).
    EXPECT_LT(test::rel_err(integrated(grid, s, "D65"), want), kFloatTolerance);
  }
  EXPECT_EQ(rep.pixels, 6u);
  EXPECT_EQ(rep.colorspace, kSrgbTexture);
  EXPECT_EQ(rep.settings.spectral.mode, Mode::reflectance);
  EXPECT_EQ(rep.counts.black, 1u);
  EXPECT_EQ(rep.out_of_gamut_pixels(), 0u);  // every sRGB colour is a reflectance
}

TEST(ImageJob, BadPixelsAreZeroSpectraCountedAndRecordedInTheHeader) {
  TempDir t;
  const std::string in = t / "bad.exr", out = t / "bad_spectral.exr";
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  // Two invalid colours, one of negative luminance, one black, two good ones.
  const std::vector<std::array<float, 3>> colours = {{nan, 0.5f, 0.5f},     {0.2f, inf, 0.1f},
                                                     {-0.3f, -0.2f, -0.1f}, {0, 0, 0},
                                                     {0.5f, 0.4f, 0.3f},    {0.1f, 0.2f, 0.6f}};
  write_rgb(in, 3, 2, OIIO::TypeFloat, interleaved(colours));
  const ImageReport rep =
      run_image_job(in, out, settings_for(ModeChoice::emission, kRec709), {}, kQuiet);
  EXPECT_EQ(rep.pixels, 6u);
  EXPECT_EQ(rep.counts.invalid, 2u);
  EXPECT_EQ(rep.counts.negative, 1u);
  EXPECT_EQ(rep.counts.black, 1u);
  EXPECT_EQ(rep.out_of_gamut_pixels(), 1u);
  const auto said = [&](const std::string& words) {
    return std::any_of(rep.warnings.begin(), rep.warnings.end(), [&](const std::string& w) {
      return w.find(words) != std::string::npos && w.find("bad.exr") != std::string::npos;
    });
  };
  EXPECT_TRUE(said("2 pixels are NaN or infinite")) << ::testing::PrintToString(rep.warnings);
  EXPECT_TRUE(said("out of gamut")) << ::testing::PrintToString(rep.warnings);
  const Image e = read_image(out);
  const Bands b = bands_of(e.spec, "S0.");
  ASSERT_EQ(b.nm.size(), 81u);
  for (int p = 0; p < 4; ++p) {
    SCOPED_TRACE(p);
    for (double v : spectrum(e, b, p)) EXPECT_EQ(v, 0.0);
  }
  const WavelengthGrid grid = b.grid();
  for (int p = 4; p < 6; ++p) {
    const auto& c = colours[p];
    EXPECT_LT(test::rel_err(integrated(grid, spectrum(e, b, p)),
                            test::rgb(test::kRec709ToXyz, c[0], c[1], c[2])),
              kFloatTolerance);
  }
  // The header says how many, so a later reader (ingest's rerun) can say it too.
  auto recorded = [&](const char* name) {
    double v = -1;
    EXPECT_TRUE(e.spec.getattribute(std::string("spectralize:") + name, OIIO::TypeDesc::DOUBLE, &v))
        << name;
    return v;
  };
  EXPECT_EQ(recorded("invalidPixels"), 2.0);
  EXPECT_EQ(recorded("negativeLuminancePixels"), 1.0);
  EXPECT_EQ(recorded("outsideLocusPixels"), 0.0);
}

// --- What is never written ---

TEST(ImageJob, AnOutputThatIsTheInputUnderAnyNameIsRefused) {
  TempDir t;
  const std::string in = t / "in.exr";
  write_rgb(in, 4, 2, OIIO::TypeFloat, interleaved(kLights));
  fs::create_hard_link(in, t.dir / "hard.exr");
  fs::create_symlink(in, t.dir / "soft.exr");
  const std::string before = bytes_of(in);
  const Settings s = settings_for(ModeChoice::emission, kRec709);
  for (const std::string& out :
       {in, (t.dir / "." / "in.exr").string(), t / "hard.exr", t / "soft.exr"}) {
    SCOPED_TRACE(out);
    test::expect_error_mentioning([&] { run_image_job(in, out, s, {}, kQuiet); },
                                  {"'" + in + "'", "refusing to overwrite"}, out);
  }
  EXPECT_EQ(bytes_of(in), before);
  EXPECT_TRUE(fs::is_symlink(t.dir / "soft.exr"));
  EXPECT_EQ(names_in(t.dir), (std::set<std::string>{"in.exr", "hard.exr", "soft.exr"}));
}

TEST(ImageJob, AThrowBeforeTheCommitLeavesNothingAtTheOutput) {
  TempDir t;
  const std::string in = t / "in.exr", out = t / "out.exr";
  write_rgb(in, 4, 2, OIIO::TypeFloat, interleaved(kLights));
  ImageJobOptions options;
  std::uint64_t seen = 0;
  options.before_commit = [&](const ImageReport& rep) {
    seen = rep.pixels;  // the finished report
    throw Error("'" + out + "': the report could not be written");
  };
  test::expect_error_mentioning(
      [&] {
        run_image_job(in, out, settings_for(ModeChoice::emission, kRec709), {}, kQuiet, options);
      },
      {"the report could not be written"}, "before_commit");
  EXPECT_EQ(seen, 8u);
  EXPECT_EQ(names_in(t.dir), std::set<std::string>{"in.exr"});  // no output, no temporary
}

// --- Spectral back to RGB ---

TEST(ImageJob, EmissionBackToRgbIsTheInput) {
  TempDir t;
  const std::string in = t / "in.exr", spectral = t / "spectral.exr", back = t / "back.exr";
  write_rgb(in, 4, 2, OIIO::TypeFloat, interleaved(kLights));
  run_image_job(in, spectral, settings_for(ModeChoice::emission, kRec709), {}, kQuiet);
  Settings s;
  s.colorspace = kRec709;
  s.half = false;
  const ToRgbReport rep = run_to_rgb_job(spectral, back, s, {}, kQuiet);
  EXPECT_EQ(rep.kind, "emissive");
  EXPECT_EQ(rep.pixels, 8u);
  EXPECT_EQ(rep.bands, 81);
  EXPECT_EQ(rep.first_nm, 380.0);
  EXPECT_EQ(rep.last_nm, 780.0);
  EXPECT_EQ(rep.invalid_pixels, 0u);
  const Image rgb = read_image(back);
  ASSERT_EQ(rgb.pixels(), 8);
  ASSERT_EQ(rgb.spec.nchannels, 3);
  EXPECT_EQ(rgb.spec.format, OIIO::TypeFloat);
  for (int p = 0; p < 8; ++p) {
    SCOPED_TRACE(p);
    const auto& c = kLights[p];
    const float peak = std::max({c[0], c[1], c[2]});
    for (int k = 0; k < 3; ++k) EXPECT_LT(std::abs(rgb.at(p, k) - c[k]) / peak, kTwiceThroughOcio);
  }
}

// White-balanced back (not "as lit"): a reflectance made of a colour is that colour again, here
// under illuminant A, whose light is far from D65's.
TEST(ImageJob, AReflectanceBackToRgbIsTheInputColour) {
  TempDir t;
  const std::string in = t / "paint.exr", spectral = t / "spectral.exr", back = t / "back.exr";
  const std::vector<std::array<float, 3>> paints = {
      {0.9f, 0.9f, 0.9f}, {0.5f, 0.2f, 0.1f}, {0.05f, 0.4f, 0.2f}, {0.1f, 0.1f, 0.6f}};
  write_rgb(in, 2, 2, OIIO::TypeFloat, interleaved(paints));
  Settings to_spectral = settings_for(ModeChoice::reflectance, kRec709);
  to_spectral.spectral.illuminant = "A";
  run_image_job(in, spectral, to_spectral, {}, kQuiet);
  Settings s;
  s.colorspace = kRec709;
  s.half = false;
  s.spectral.illuminant = "A";
  const ToRgbReport rep = run_to_rgb_job(spectral, back, s, {}, kQuiet);
  EXPECT_EQ(rep.kind, "reflective");
  EXPECT_EQ(rep.settings.spectral.illuminant, "A");
  const Image rgb = read_image(back);
  ASSERT_EQ(rgb.pixels(), 4);
  for (int p = 0; p < 4; ++p) {
    SCOPED_TRACE(p);
    const auto& c = paints[p];
    const float peak = std::max({c[0], c[1], c[2]});
    for (int k = 0; k < 3; ++k) EXPECT_LT(std::abs(rgb.at(p, k) - c[k]) / peak, kTwiceThroughOcio);
  }
}

TEST(ImageJob, BackToRgbRefusesTheInputAndLeavesNothingWhenStopped) {
  TempDir t;
  const std::string in = t / "in.exr", spectral = t / "spectral.exr";
  write_rgb(in, 4, 2, OIIO::TypeFloat, interleaved(kLights));
  run_image_job(in, spectral, settings_for(ModeChoice::emission, kRec709), {}, kQuiet);
  const std::string before = bytes_of(spectral);
  Settings s;
  s.colorspace = kRec709;
  s.half = false;
  test::expect_error_mentioning([&] { run_to_rgb_job(spectral, spectral, s, {}, kQuiet); },
                                {"'" + spectral + "'", "refusing to overwrite"}, "the input");
  EXPECT_EQ(bytes_of(spectral), before);
  std::uint64_t seen = 0;
  test::expect_error_mentioning(
      [&] {
        run_to_rgb_job(spectral, t / "back.exr", s, {}, kQuiet, [&](const ToRgbReport& rep) {
          seen = rep.pixels;
          throw Error("stopped before the commit");
        });
      },
      {"stopped before the commit"}, "before_commit");
  EXPECT_EQ(seen, 8u);
  EXPECT_EQ(names_in(t.dir), (std::set<std::string>{"in.exr", "spectral.exr"}));
}

}  // namespace
}  // namespace spectralize
