// Message helpers (text/strings.h): long values are clipped, whole UTF-8 characters kept.

#include "text/strings.h"

#include <gtest/gtest.h>

#include "colour/colour_space.h"
#include "spectralize/core/error.h"

namespace spectralize {
namespace {

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

}  // namespace
}  // namespace spectralize
