// Spectral channel names (imagefile/spectral_channel.h) against the layout's definition
// (Fichet, Pacanowski & Wilkie, JCGT 2021; docs/DESIGN.md §7): its reference regex, its SI
// prefixes and units, the comma as decimal separator, and six decimals when written.

#include "imagefile/spectral_channel.h"

#include <gtest/gtest.h>

#include <string>

namespace spectralize {
namespace {

TEST(SpectralChannel, NamesAreWrittenAsTheReferenceWritesThem) {
  EXPECT_EQ(spectral_channel_name(SpectralChannel::Kind::emissive, 380), "S0.380,000000nm");
  EXPECT_EQ(spectral_channel_name(SpectralChannel::Kind::reflective, 552.5), "T.552,500000nm");
  EXPECT_EQ(spectral_channel_name(SpectralChannel::Kind::emissive, 700, 2), "S2.700,000000nm");
  EXPECT_EQ(spectral_channel_name(SpectralChannel::Kind::reflective, 0.25), "T.0,250000nm");
}

TEST(SpectralChannel, ParsesTheLayoutsUnitsAndPrefixes) {
  struct Case {
    const char* name;
    SpectralChannel::Kind kind;
    int stokes;
    double nm;
  };
  const Case cases[] = {
      {"S0.550,000000nm", SpectralChannel::Kind::emissive, 0, 550},
      {"S3.550nm", SpectralChannel::Kind::emissive, 3, 550},
      {"T.0,55um", SpectralChannel::Kind::reflective, 0, 550},
      {"T.5,5E2nm", SpectralChannel::Kind::reflective, 0, 550},
      {"T.550000pm", SpectralChannel::Kind::reflective, 0, 550},
      {"S1.0,00000055m", SpectralChannel::Kind::emissive, 1, 550},
  };
  for (const Case& c : cases) {
    const auto parsed = parse_spectral_channel(c.name);
    ASSERT_TRUE(parsed) << c.name;
    EXPECT_EQ(parsed->kind, c.kind) << c.name;
    EXPECT_EQ(parsed->stokes, c.stokes) << c.name;
    EXPECT_NEAR(parsed->wavelength_nm, c.nm, 1e-9 * c.nm) << c.name;
  }
  // A frequency is a wavelength too: 545.077 THz is 550 nm (c = 299792458 m/s).
  const auto thz = parse_spectral_channel("S0.545,07719THz");
  ASSERT_TRUE(thz);
  EXPECT_NEAR(thz->wavelength_nm, 550.0, 1e-3);
}

TEST(SpectralChannel, OtherChannelsAreNotSpectral) {
  for (const char* name : {"R", "G", "B", "A", "Y", "S4.550nm", "S0.550", "T.550nx", "T.5x0nm",
                           "S0.550,0nm.extra", "s0.550nm", "T550nm", ""}) {
    EXPECT_FALSE(parse_spectral_channel(name)) << name;
  }
}

}  // namespace
}  // namespace spectralize
