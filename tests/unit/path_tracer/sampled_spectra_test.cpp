// Sampled spectra: the piecewise-linear function through the samples, zero outside the grid,
// times the texel's scale; spectral EXRs (written here with OIIO) read back by wavelength.

#include "path_tracer/sampled_spectra.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "../file_test_support.h"
#include "../test_support.h"

namespace spectralize::path_tracer {
namespace {

std::vector<float> eval_at(const SampledSpectra& s, std::uint32_t texel, std::array<float, 4> nm) {
  WavelengthPacket p;
  p.nm = nm;
  std::vector<float> out(4);
  s.eval(texel, std::span<const WavelengthPacket>(&p, 1), out.data());
  return out;
}

TEST(SampledSpectra, PiecewiseLinearZeroOutsideScaledPerTexel) {
  // Two spectra on 400, 410, 420 nm; texel 0 -> spectrum 1, texel 1 -> spectrum 0 times 2.
  const SampledSpectra s(400, 10, 3, {0.1f, 0.3f, 0.2f, 1.0f, 0.0f, 0.5f}, {1, 0}, {1.0f, 2.0f});
  EXPECT_EQ(s.texels(), 2u);
  const auto a = eval_at(s, 0, {400, 405, 417.5f, 420});
  EXPECT_FLOAT_EQ(a[0], 1.0f);
  EXPECT_FLOAT_EQ(a[1], 0.5f);
  EXPECT_FLOAT_EQ(a[2], 0.375f);
  EXPECT_FLOAT_EQ(a[3], 0.5f);
  const auto b = eval_at(s, 1, {399.9f, 410, 415, 420.1f});
  EXPECT_EQ(b[0], 0.0f);
  EXPECT_FLOAT_EQ(b[1], 0.6f);
  EXPECT_FLOAT_EQ(b[2], 0.5f);
  EXPECT_EQ(b[3], 0.0f);
}

TEST(SampledSpectra, RefusesInconsistentData) {
  auto partial = [] { SampledSpectra(400, 10, 3, {0, 0, 0, 0}, {0}); };
  test::expect_error_mentioning(partial, {"whole spectra"}, "partial");
  auto bad_index = [] { SampledSpectra(400, 10, 2, {0, 0}, {1}); };
  test::expect_error_mentioning(bad_index, {"texel spectrum 1 of 1"}, "index");
  auto extra_scales = [] { SampledSpectra(400, 10, 2, {0, 0}, {0}, {1, 1}); };
  test::expect_error_mentioning(extra_scales, {"2 scales for 1 texels"}, "scales");
}

// Writes a 2 x 1 EXR with channels R, T.420,000000nm, T.400,000000nm, T.410,000000nm (not in
// wavelength order).
std::string write_exr(const std::filesystem::path& dir, bool even) {
  const std::string path = (dir / (even ? "even.exr" : "uneven.exr")).string();
  OIIO::ImageSpec spec(2, 1, 4, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"R", "T.420,000000nm", "T.400,000000nm",
                       even ? "T.410,000000nm" : "T.405,000000nm"};
  const float px[8] = {9, 0.3f, 0.1f, 0.2f, 9, 0.6f, 0.4f, 0.5f};
  auto out = OIIO::ImageOutput::create(path);
  EXPECT_TRUE(out && out->open(path, spec));
  EXPECT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px));
  out->close();
  return path;
}

TEST(SampledSpectra, ReadsSpectralExrsByWavelength) {
  const test::TempDir t("sampled_spectra");
  const std::filesystem::path& dir = t.dir;
  const SampledSpectra s = SampledSpectra::read_exr(write_exr(dir, true), 2.0f);
  EXPECT_EQ(s.texels(), 2u);
  EXPECT_EQ(s.bands(), 3u);
  const auto v = eval_at(s, 1, {400, 410, 420, 415});
  EXPECT_FLOAT_EQ(v[0], 0.8f);
  EXPECT_FLOAT_EQ(v[1], 1.0f);
  EXPECT_FLOAT_EQ(v[2], 1.2f);
  EXPECT_FLOAT_EQ(v[3], 1.1f);
  const std::string uneven = write_exr(dir, false);
  test::expect_error_mentioning([&] { SampledSpectra::read_exr(uneven); },
                                {uneven, "evenly spaced"}, "uneven");
  test::expect_error_mentioning([&] { SampledSpectra::read_exr((dir / "none.exr").string()); },
                                {"none.exr"}, "missing");
}

}  // namespace
}  // namespace spectralize::path_tracer
