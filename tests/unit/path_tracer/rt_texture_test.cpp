// spectralize::rt as a texture (path_tracer/rt_texture.h), on the natural model's Linear
// Rec.709 tables that `spectralize table` makes (the tracer_tables fixture): white (1, 1, 1) is
// rho == 1 and black rho == 0 at every visible wavelength (the only reflectances <= 1 of Y 1 and
// 0), a light's spectrum is times its scale, each texel is its own RGB's, and lookups that were
// mapped into the gamut or invalid (NaN, negative luminance) are counted once per lookup,
// invalid ones giving the zero spectrum.

#include "path_tracer/rt_texture.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <vector>

namespace spectralize::path_tracer {
namespace {

using TablePtr = std::unique_ptr<spz_table, decltype(&spz_table_free)>;

TablePtr load(const std::string& name) {
  const std::string path = std::string(TRACER_TABLES) + "/" + name;
  char error[512] = "";
  TablePtr t(spz_table_load(path.c_str(), error, sizeof error), &spz_table_free);
  EXPECT_TRUE(t) << error << " (made by ctest's tracer_tables fixture)";
  return t;
}

// Two packets at visible wavelengths, where every cmf is far from 0.
std::vector<WavelengthPacket> packets() {
  std::vector<WavelengthPacket> p(2);
  const float nm[8] = {440, 480, 520, 560, 600, 620, 640, 660};
  for (int k = 0; k < 8; ++k) p[k / 4].nm[k % 4] = nm[k];
  return p;
}

std::vector<float> eval(const RtTexture& t, std::uint32_t texel) {
  const std::vector<WavelengthPacket> p = packets();
  std::vector<float> out(p.size() * kLanes, -1.0f);
  t.eval(texel, p, out.data());
  return out;
}

TEST(RtTexture, WhiteIsOneBlackIsZeroAndEachTexelIsItsOwn) {
  const TablePtr table = load("srgb_reflectance_natural.spztab");
  ASSERT_TRUE(table);
  const RtTexture t(table.get(), {0.0f, 0.0f, 0.0f, 1.0f, 1.0f, 1.0f, 0.0f, 0.0f, 0.0f});
  ASSERT_EQ(t.texels(), 3u);
  for (float v : eval(t, 1)) EXPECT_NEAR(v, 1.0f, 1e-4);
  for (std::uint32_t texel : {0u, 2u})
    for (float v : eval(t, texel)) EXPECT_NEAR(v, 0.0f, 1e-6);
  EXPECT_EQ(t.mapped(), 0);
  EXPECT_EQ(t.invalid(), 0);
}

TEST(RtTexture, ALightsSpectrumIsTimesItsScale) {
  const TablePtr table = load("srgb_emission_natural.spztab");
  ASSERT_TRUE(table);
  const std::vector<float> rgb = {0.8f, 0.6f, 0.3f};
  const RtTexture plain(table.get(), rgb), bright(table.get(), rgb, 2.5f);
  const std::vector<float> a = eval(plain, 0), b = eval(bright, 0);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_GT(a[i], 0.0f);
    EXPECT_NEAR(b[i], 2.5f * a[i], 1e-6f * b[i]) << i;
  }
}

TEST(RtTexture, MappedAndInvalidLookupsAreCountedOncePerLookup) {
  const TablePtr table = load("srgb_reflectance_natural.spztab");
  ASSERT_TRUE(table);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // A reflectance above 1 (outside the solid: mapped), NaN and a negative luminance (invalid).
  const RtTexture t(table.get(),
                    {1.5f, 1.5f, 1.5f, nan, 0.5f, 0.5f, -1.0f, -1.0f, -1.0f, 0.5f, 0.5f, 0.5f});
  const std::vector<float> mapped = eval(t, 0);
  EXPECT_EQ(t.mapped(), 1);  // one lookup, two packets
  // Mapped toward black at constant chromaticity: inside the solid, still a reflectance.
  for (float v : mapped) {
    EXPECT_GT(v, 0.0f);
    EXPECT_LE(v, 1.0f + 1e-4f);
  }
  EXPECT_EQ(t.invalid(), 0);
  for (std::uint32_t texel : {1u, 2u})
    for (float v : eval(t, texel)) EXPECT_EQ(v, 0.0f) << "texel " << texel;
  EXPECT_EQ(t.invalid(), 2);
  eval(t, 3);
  eval(t, 0);
  EXPECT_EQ(t.mapped(), 2);
  EXPECT_EQ(t.invalid(), 2);
}

}  // namespace
}  // namespace spectralize::path_tracer
