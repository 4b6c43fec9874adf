// WavelengthGrid: the default grid, parsing of "start:end:step", the errors a user sees for bad
// grids, and the to_string() round trip (docs/DESIGN.md §3).

#include "spectralize/core/wavelength_grid.h"

#include <gtest/gtest.h>

#include "test_support.h"

namespace spectralize {
namespace {

using test::expect_error_mentioning;

TEST(WavelengthGrid, DefaultIs380To780At5nm) {
  WavelengthGrid g;
  // 380, 385, ..., 780: (780 - 380) / 5 + 1 = 81 samples; grid points are exact in binary.
  EXPECT_EQ(g.size(), 81u);
  EXPECT_EQ(g[0], 380.0);
  EXPECT_EQ(g[80], 780.0);
  EXPECT_EQ(g.end(), 780.0);
  EXPECT_EQ(g.step(), 5.0);
  EXPECT_EQ(g, WavelengthGrid::parse("380:780:5"));
}

TEST(WavelengthGrid, ParsesValidGrids) {
  struct Case {
    const char* text;
    std::size_t size;
    double start, end, step;
  } cases[] = {
      {"400:700:10", 31, 400, 700, 10},    {"360:830:0.5", 941, 360, 830, 0.5},
      {"360:830:1", 471, 360, 830, 1},     {"380.5:779.5:3", 134, 380.5, 779.5, 3},
      {"380:780:0.5", 801, 380, 780, 0.5}, {"400:410:5", 3, 400, 410, 5},
      {"400:701:7", 44, 400, 701, 7},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.text);
    WavelengthGrid g = WavelengthGrid::parse(c.text);
    // Sample counts are (end - start) / step + 1, computed by hand above.
    EXPECT_EQ(g.size(), c.size);
    EXPECT_EQ(g.start(), c.start);
    EXPECT_EQ(g.step(), c.step);
    // The last sample must land on `end` (to rounding of start + i*step, 1e-9 nm).
    EXPECT_NEAR(g.end(), c.end, 1e-9);
    EXPECT_NEAR(g[g.size() - 1], c.end, 1e-9);
    EXPECT_EQ(g, WavelengthGrid(c.start, c.end, c.step));
  }
}

TEST(WavelengthGrid, RejectsBadGridsWithTheReason) {
  auto parse = [](const char* s) { return [s] { (void)WavelengthGrid::parse(s); }; };
  // The words are the reason a user needs to read in the message.
  expect_error_mentioning(parse(""), {"start:end:step"}, "empty string");
  expect_error_mentioning(parse("a:b:c"), {"not a number"}, "a:b:c");
  expect_error_mentioning(parse("380:780"), {"start:end:step"}, "two fields");
  expect_error_mentioning(parse("380:780:5:1"), {}, "four fields");
  expect_error_mentioning(parse("380:780:5nm"), {"not a number"}, "trailing unit");
  expect_error_mentioning(parse("780:380:5"), {"reversed"}, "reversed");
  expect_error_mentioning(parse("380:780:0"), {"positive"}, "zero step");
  expect_error_mentioning(parse("380:780:-5"), {"positive"}, "negative step");
  expect_error_mentioning(parse("380:780:0.25"), {"0.5"}, "step below 0.5 nm");
  expect_error_mentioning(parse("350:780:5"), {"360..830"}, "start below 360");
  expect_error_mentioning(parse("380:900:5"), {"360..830"}, "end above 830");
  expect_error_mentioning(parse("380:781:5"), {"whole number"}, "non-integral count");
  expect_error_mentioning(parse("400:700:7"), {"whole number"}, "300 nm is not a multiple of 7");
  expect_error_mentioning(parse("380:385:5"), {"at least 3"}, "two samples");
  expect_error_mentioning(parse("380:380:5"), {"at least 3"}, "one sample");
  expect_error_mentioning(parse("nan:780:5"), {}, "NaN start");
  expect_error_mentioning([] { WavelengthGrid(380, 780, std::nan("")); }, {"finite"}, "NaN step");
}

TEST(WavelengthGrid, ToStringRoundTrips) {
  for (const char* text :
       {"380:780:5", "400:700:10", "360:830:0.5", "380.5:779.5:3", "400:701:7"}) {
    SCOPED_TRACE(text);
    WavelengthGrid g = WavelengthGrid::parse(text);
    // These inputs are already in the shortest form, so the text itself must come back.
    EXPECT_EQ(g.to_string(), text);
    EXPECT_EQ(WavelengthGrid::parse(g.to_string()), g);
  }
  // A non-canonical spelling parses to the same grid and prints canonically.
  EXPECT_EQ(WavelengthGrid::parse("380.0:780.00:5.0").to_string(), "380:780:5");
}

}  // namespace
}  // namespace spectralize
