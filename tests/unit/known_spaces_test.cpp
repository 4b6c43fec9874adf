// The standard spaces known without a config (colour/known_spaces.h): chromaticities matched
// up to chromatic adaptation, the encodings, the interop IDs built of both and the usual names.
// Oracles: the sRGB ICC profile's published D50-adapted colorants, the standards' primaries and
// curves as published, and the AP0/AP1 primaries as OCIO's own Bradford transform adapts them.

#include "colour/known_spaces.h"

#include <gtest/gtest.h>

#include <string>

namespace spectralize {
namespace {

TEST(KnownSpaces, ChromaticitiesMatchUpToTheAdaptationOfTheirWhite) {
  // Rec.709 primaries adapted to a D50 white, as an ICC sRGB profile's colorants state them
  // (rXYZ 0.4361 0.2225 0.0139, gXYZ 0.3851 0.7169 0.0971, bXYZ 0.1431 0.0606 0.7141) and as
  // Photoshop writes EXR chromaticities.
  const float d50_709[8] = {0.6484f, 0.3309f, 0.3212f, 0.5978f, 0.1559f, 0.0660f, 0.3457f, 0.3585f};
  const float rec709[8] = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};
  const auto adapted = adapt_chromaticities_to_d65(d50_709);
  EXPECT_LT(chromaticity_difference(adapted.data(), rec709), 1e-4);
  EXPECT_EQ(interop_id_of_chromaticities(d50_709), "lin_rec709_scene");
  // Rec.709's own primaries with a D50 white are another space (0.02 away once adapted).
  const float unadapted[8] = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3457f, 0.3585f};
  EXPECT_GT(chromaticity_difference(adapt_chromaticities_to_d65(unadapted).data(), rec709), 0.01);
  EXPECT_EQ(interop_id_of_chromaticities(unadapted), "");
  // D65 input is unchanged; AP1 with the ACES white is ACEScg; Rec.2020 is not AP1.
  EXPECT_LT(chromaticity_difference(adapt_chromaticities_to_d65(rec709).data(), rec709), 1e-6);
  const float ap1[8] = {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f};
  EXPECT_EQ(interop_id_of_chromaticities(ap1), "lin_ap1_scene");
  const float rec2020[8] = {0.708f, 0.292f, 0.170f, 0.797f, 0.131f, 0.046f, 0.3127f, 0.3290f};
  EXPECT_EQ(interop_id_of_chromaticities(rec2020), "lin_rec2020_scene");
}

TEST(KnownSpaces, EveryStandardAdaptsToWhatOcioSeesOfIt) {
  // The adapted chromaticities were measured through OCIO's built-in ACES transforms; the
  // project's Bradford adaptation of the standards' own numbers gives them.
  for (const KnownPrimaries& k : known_primaries()) {
    SCOPED_TRACE(std::string(k.id));
    EXPECT_LT(chromaticity_difference(adapt_chromaticities_to_d65(k.native.data()).data(),
                                      k.adapted.data()),
              2e-4);
    EXPECT_EQ(known_primaries_of(k.adapted.data()), &k);
    EXPECT_EQ(interop_id_of_chromaticities(k.native.data()), "lin_" + std::string(k.id) + "_scene");
  }
}

TEST(KnownSpaces, EncodingsAreThePublishedCurves) {
  auto named = [](std::string_view id, double exponent) -> const KnownEncoding* {
    for (const KnownEncoding& e : known_encodings())
      if (e.id == id && e.transfer.exponent == exponent) return &e;
    return nullptr;
  };
  ASSERT_TRUE(named("lin", 1));
  EXPECT_EQ(known_encodings().front().id, "lin");  // linear is tried first
  const KnownEncoding* srgb = named("srgb", 2.4);
  ASSERT_TRUE(srgb);
  // IEC 61966-2-1: 0.5 encodes 0.214041 linear; the linear segment below 0.04045.
  EXPECT_NEAR((*srgb)(0.5), 0.2140411, 1e-6);
  EXPECT_NEAR((*srgb)(0.04), 0.04 / 12.92, 1e-12);
  const KnownEncoding* adobe = named("g22", 563.0 / 256);
  ASSERT_TRUE(adobe);
  EXPECT_NEAR((*adobe)(0.5), 0.2177555, 1e-6);  // Adobe RGB (1998): 2 + 51/256
  EXPECT_TRUE(named("g22", 2.2) && named("g18", 1.8) && named("g24", 2.4) && named("g26", 2.6));
}

TEST(KnownSpaces, InteropIdsAreTheForumsCombinationsOnly) {
  EXPECT_EQ(known_interop_id("srgb", "rec709", false), "srgb_rec709_scene");
  EXPECT_EQ(known_interop_id("srgb", "rec709", true), "srgb_rec709_display");
  EXPECT_EQ(known_interop_id("lin", "ap1", false), "lin_ap1_scene");
  EXPECT_EQ(known_interop_id("g26", "p3d65", true), "g26_p3d65_display");
  // Combinations the Color Interop Forum does not name get no ID.
  EXPECT_EQ(known_interop_id("g26", "ap0", false), "");
  EXPECT_EQ(known_interop_id("lin", "ap1", true), "");
  EXPECT_TRUE(looks_like_interop_id("lin_rec709_scene"));
  EXPECT_TRUE(looks_like_interop_id("data"));
  EXPECT_FALSE(looks_like_interop_id("Linear Rec.709 (sRGB)"));
  EXPECT_FALSE(looks_like_interop_id("lin_rec709"));
  EXPECT_FALSE(looks_like_interop_id("_rec709_scene"));
}

TEST(KnownSpaces, UsualNamesAreTriedInOrder) {
  const auto names = usual_names_of("lin_ap1_scene");
  ASSERT_EQ(names.size(), 3u);
  EXPECT_EQ(names[0], "ACEScg");
  EXPECT_EQ(usual_names_of("lin_p3d65_scene").size(), 2u);
  EXPECT_TRUE(usual_names_of("g26_p3d65_display").empty());
}

}  // namespace
}  // namespace spectralize
