// Decimal numbers typed by users (core/decimal_number.h): what is accepted, and a message that
// says what is wrong with each kind of text. Oracle: the values as written in decimal here.

#include "core/decimal_number.h"

#include <gtest/gtest.h>

#include "spectralize/core/error.h"
#include "test_support.h"

namespace spectralize {
namespace {

TEST(DecimalNumber, DecimalTextIsReadAsWritten) {
  const std::pair<const char*, double> cases[] = {
      {"0.25", 0.25}, {"+2.5e-1", 0.25}, {"-1", -1.0}, {".5", 0.5},
      {"5.", 5.0},    {"1E3", 1000.0},   {"-0", -0.0}, {"1e-300", 1e-300}};
  for (const auto& [text, want] : cases) EXPECT_EQ(decimal_number(text), want) << text;
}

TEST(DecimalNumber, EachKindOfWrongTextIsNamedForWhatItIs) {
  const std::pair<const char*, const char*> cases[] = {
      {"0x1p-2", "'0x1p-2' is a hexadecimal number; write it in decimal (0.25)"},
      {"-0X10", "'-0X10' is a hexadecimal number; write it in decimal (-16)"},
      {"0xg", "'0xg' is not a number"},
      {"", "'' is not a number"},
      {"1,5", "'1,5' is not a number"},
      {"abc", "'abc' is not a number"},
      {"+-1", "'+-1' is not a number"},
      {"1.5 ", "'1.5 ' is not a number"},
      {"1e999", "'1e999' is out of the range of a double"},
      {"inf", "'inf' is not a finite number"},
      {"-nan", "'-nan' is not a finite number"}};
  for (const auto& [text, want] : cases)
    EXPECT_EQ(test::error_message([&] { decimal_number(text); }).rfind(want, 0), 0u)
        << text << ": " << test::error_message([&] { decimal_number(text); });
}

}  // namespace
}  // namespace spectralize
