// The spectral layout of other tools' files (pipeline/rgb_from_spectral.h,
// analyse_spectral_layout): channels sorted by wavelength, strange ones named, bispectral,
// out-of-range and mixed layouts refused.

#include "pipeline/rgb_from_spectral.h"

#include <gtest/gtest.h>

#include "spectralize/core/error.h"

namespace spectralize {
namespace {

OIIO::ImageSpec spec_of(std::vector<std::string> names, OIIO::TypeDesc type = OIIO::TypeFloat) {
  OIIO::ImageSpec spec(8, 8, static_cast<int>(names.size()), type);
  spec.channelnames = std::move(names);
  spec.alpha_channel = -1;
  return spec;
}

TEST(SpectralLayout, ChannelsSortedByWavelengthAndStrangeOnesNamed) {
  const auto info = analyse_spectral_layout(
      spec_of({"A", "S0.1000,0nm", "S0.950,0nm", "S0.0,55um", "S0.5x0nm", "R"}), "f.exr");
  EXPECT_EQ(info.wavelengths, (std::vector<double>{550, 950, 1000}));
  EXPECT_EQ(info.band_channels, (std::vector<int>{3, 2, 1}));
  EXPECT_EQ(info.alpha, 0);
  EXPECT_EQ(info.unparsed, std::vector<std::string>{"S0.5x0nm"});
  EXPECT_THROW(
      analyse_spectral_layout(spec_of({"T.500,0nm", "T.500,0nm.510,0nm", "T.510,0nm"}), "bi.exr"),
      Error);
  EXPECT_THROW(analyse_spectral_layout(spec_of({"S0.900,0nm", "S0.950,0nm"}), "ir.exr"), Error);
  EXPECT_THROW(analyse_spectral_layout(spec_of({"S0.500,0nm", "T.600,0nm"}), "mixed.exr"), Error);
}

}  // namespace
}  // namespace spectralize
