// The baseline's texture (path_tracer/sigmoid_texture.h): each texel's RGB is clamped to
// [0, 1] before the table's fetch, as pbrt-v4's RGBAlbedoSpectrum does (so an out-of-range texel
// is its clamped colour's spectrum), a grey is a flat spectrum (the sigmoid of a constant), and
// each packet's four values land in the packet's place of the output.

#include "path_tracer/sigmoid_texture.h"

#include <gtest/gtest.h>

#include <vector>

#include "../test_support.h"

namespace spectralize::path_tracer {
namespace {

// A small table (8^3 nodes a block: milliseconds) of Linear Rec.709.
const baseline::SigmoidTable& table() {
  static const baseline::SigmoidFitter fitter(test::kRec709ToXyz);
  static const baseline::SigmoidTable t(fitter, 8, 1);
  return t;
}

std::vector<WavelengthPacket> packets() {
  std::vector<WavelengthPacket> p(3);
  const float nm[12] = {400, 430, 460, 490, 520, 550, 580, 610, 640, 670, 700, 730};
  for (int k = 0; k < 12; ++k) p[k / 4].nm[k % 4] = nm[k];
  return p;
}

std::vector<float> eval(const SigmoidTexture& t, std::uint32_t texel) {
  const std::vector<WavelengthPacket> p = packets();
  std::vector<float> out(p.size() * kLanes, -1.0f);
  t.eval(texel, p, out.data());
  return out;
}

TEST(SigmoidTexture, ClampsEachTexelToTheUnitCubeFirst) {
  // Texels 0/1, 2/3, 4/5: a colour and the same colour with components beyond [0, 1].
  const SigmoidTexture t(table(), {1.0f, 0.3f, 0.0f, 1.7f, 0.3f, -0.4f,  //
                                   0.2f, 0.6f, 0.9f, 0.2f, 0.6f, 0.9f,   //
                                   0.0f, 0.0f, 1.0f, -3.0f, -1.0f, 5.0f});
  ASSERT_EQ(t.texels(), 6u);
  for (std::uint32_t texel : {0u, 2u, 4u}) {
    const std::vector<float> inside = eval(t, texel), outside = eval(t, texel + 1);
    for (std::size_t i = 0; i < inside.size(); ++i) {
      EXPECT_EQ(inside[i], outside[i]) << "texel " << texel << " value " << i;
      EXPECT_GT(inside[i], 0.0f);  // a sigmoid: strictly inside (0, 1)
      EXPECT_LT(inside[i], 1.0f);
    }
  }
}

TEST(SigmoidTexture, AGreyIsFlatAndEachPacketFillsItsOwnLanes) {
  // Texel 0 a grey, texel 1 a red: different texels give their own spectra.
  const SigmoidTexture t(table(), {0.5f, 0.5f, 0.5f, 0.8f, 0.1f, 0.1f});
  const std::vector<float> grey = eval(t, 0), red = eval(t, 1);
  for (float v : grey) EXPECT_NEAR(v, grey[0], 2e-3);  // a constant's sigmoid
  EXPECT_NEAR(grey[0], 0.5, 0.05);
  // Red reflects more at 700 nm (packet 2, lane 2) than at 460 nm (packet 0, lane 2).
  EXPECT_GT(red[10], red[2] + 0.3f);
  // One packet at a time gives the same values as the three together, in order.
  const std::vector<WavelengthPacket> all = packets();
  for (std::size_t k = 0; k < all.size(); ++k) {
    float out[kLanes];
    t.eval(1, std::span<const WavelengthPacket>(&all[k], 1), out);
    for (int i = 0; i < kLanes; ++i) EXPECT_EQ(out[i], red[k * kLanes + i]) << k << ", " << i;
  }
}

}  // namespace
}  // namespace spectralize::path_tracer
