// Text helpers (text/strings.h): long values are clipped, whole UTF-8 characters kept; the
// hash of file names, keys and table checksums is the published FNV-1a.

#include "text/strings.h"

#include <gtest/gtest.h>

#include "colour/colour_space.h"
#include "spectralize/core/error.h"

namespace spectralize {
namespace {

TEST(Fnv1a, IsThePublishedHashSoOtherToolsCanCheckOurFiles) {
  // The published FNV-1a 64 test vectors (offset basis 0xcbf29ce484222325, prime 0x100000001b3):
  // what a reader of the table format written from its specification computes.
  EXPECT_EQ(fnv1a(""), 0xcbf29ce484222325ull);
  EXPECT_EQ(fnv1a("a"), 0xaf63dc4c8601ec8cull);
  EXPECT_EQ(fnv1a("foobar"), 0x85944171f73967e8ull);
  // Continuing a hash is hashing the whole.
  EXPECT_EQ(fnv1a("bar", fnv1a("foo")), fnv1a("foobar"));
  EXPECT_EQ(hex64(fnv1a("a")), "af63dc4c8601ec8c");
}

TEST(Messages, LongValuesAreClipped) {
  const std::string big(100000, 'x');
  EXPECT_LT(clip(big).size(), 120u);
  EXPECT_NE(clip(big).find("100000 bytes"), std::string::npos);
  EXPECT_EQ(clip("short"), "short");
  EXPECT_LT(quote(big).size(), 120u);
  try {
    ColourSpaces::load().resolve(big);
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_LT(std::string(e.what()).size(), 5000u);
  }
}

TEST(Messages, ClipShortensLongValuesAtACharacterBoundary) {
  EXPECT_EQ(clip("short", 80), "short");
  const std::string long_value(1000, 'v');
  const std::string clipped = clip(long_value, 80);
  std::string want(80, 'v');
  want += "...";  // not operator+: GCC 12 may see a bogus out-of-bounds copy in it
  EXPECT_EQ(clipped.substr(0, 83), want);
  EXPECT_LT(clipped.size(), 120u);
  // "é" is two bytes: a cut at 5 bytes would split the third one.
  const std::string accents = "\xC3\xA9\xC3\xA9\xC3\xA9\xC3\xA9";
  EXPECT_EQ(clip(accents, 5).substr(0, 7), "\xC3\xA9\xC3\xA9...");
}

}  // namespace
}  // namespace spectralize
