// Colour tags (colour/colour_tags.h): known spaces get their standards' primaries and interop
// IDs; oracles are the standards' published primaries.

#include "colour/colour_tags.h"

#include <gtest/gtest.h>

#include "colour/colour_space.h"
#include "file_test_support.h"

namespace spectralize {
namespace {

using test::spec_of;

TEST(ColourTags, KnownSpacesGetTheirStandardsPrimariesAndIds) {
  const ColourSpaces spaces = ColourSpaces::load();
  EXPECT_EQ(spaces.interop_id("ACEScg"), "lin_ap1_scene");
  EXPECT_EQ(spaces.interop_id("Linear Rec.709 (sRGB)"), "lin_rec709_scene");
  EXPECT_EQ(spaces.interop_id("sRGB - Texture"), "srgb_rec709_scene");
  EXPECT_EQ(spaces.interop_id("Adobe RGB (1998) - Texture"), "g22_adobergb_scene");
  EXPECT_EQ(spaces.interop_id("Raw"), "data");
  EXPECT_EQ(spaces.interop_id("ACEScct"), "");
  EXPECT_TRUE(spaces.is_linear("ACEScg"));
  EXPECT_FALSE(spaces.is_linear("sRGB - Texture"));
  OIIO::ImageSpec spec = spec_of({"R", "G", "B"});
  spec.attribute("colorInteropID", "lin_ap0_scene");
  spec.attribute("ICCProfile:device_class", "mntr");
  tag_colour_space(spec, spaces, "Linear Rec.2020");
  EXPECT_EQ(spec.get_string_attribute("colorInteropID"), "lin_rec2020_scene");
  EXPECT_EQ(spec.find_attribute("ICCProfile:device_class"), nullptr);
  const OIIO::ParamValue* c =
      spec.find_attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8));
  ASSERT_TRUE(c);
  EXPECT_NEAR(static_cast<const float*>(c->data())[0], 0.708f, 1e-5);
  // An encoded space has its primaries' chromaticities too (they say nothing of the transfer).
  tag_colour_space(spec, spaces, "sRGB - Texture");
  c = spec.find_attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8));
  ASSERT_TRUE(c);
  EXPECT_NEAR(static_cast<const float*>(c->data())[0], 0.64f, 1e-5);
  // Transfer functions an ICC curve states, measured through OCIO.
  EXPECT_EQ(spaces.transfer("sRGB - Texture")->kind, IccTransfer::srgb);
  EXPECT_EQ(spaces.transfer("ACEScg")->kind, IccTransfer::linear);
  EXPECT_EQ(spaces.transfer("Gamma 2.2 Rec.709 - Texture")->exponent, 2.2);
  EXPECT_EQ(spaces.transfer("Adobe RGB (1998) - Texture")->exponent, 563.0 / 256);
  EXPECT_FALSE(spaces.transfer("ACEScct"));
  EXPECT_FALSE(spaces.transfer("Raw"));
}

}  // namespace
}  // namespace spectralize
