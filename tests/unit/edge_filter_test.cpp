// The paper's edge-peak filter (include/spectralize/core/edge_filter.h, docs/DESIGN.md §2):
// EdgeFilter's parsing, text form and drop counts, and EdgeBands, the samples within 20 nm of
// either end of the grid whose peaks "auto" removes, against the mean over 400-700 nm. Oracles:
// the bands and means computed here from the wavelengths.

#include "spectralize/core/edge_filter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <vector>

#include "spectralize/core/wavelength_grid.h"
#include "test_support.h"

namespace spectralize {
namespace {

using test::expect_error_mentioning;

std::vector<double> wavelengths(double start, double end, double step) {
  std::vector<double> nm;
  for (double w = start; w <= end + 1e-9; w += step) nm.push_back(w);
  return nm;
}

// --- EdgeFilter ---

TEST(EdgeFilter, ParsesFractionsPercentagesCountsAndNone) {
  EdgeFilter f = EdgeFilter::parse("0.7");
  EXPECT_EQ(f.kind(), EdgeFilter::Kind::fraction);
  EXPECT_DOUBLE_EQ(f.value(), 0.7);
  EdgeFilter p = EdgeFilter::parse("70%");
  EXPECT_EQ(p.kind(), EdgeFilter::Kind::fraction);
  EXPECT_DOUBLE_EQ(p.value(), 0.7);  // 70/100 rounds to the double nearest 0.7
  EdgeFilter c = EdgeFilter::parse("1000");
  EXPECT_EQ(c.kind(), EdgeFilter::Kind::count);
  EXPECT_EQ(c.value(), 1000.0);
  EdgeFilter n = EdgeFilter::parse("none");
  EXPECT_EQ(n, EdgeFilter());
  EXPECT_EQ(n.drop_count(12345), 0u);
  EXPECT_EQ(EdgeFilter::parse("0").drop_count(12345), 0u);  // a count of zero drops nothing
  EdgeFilter a = EdgeFilter::parse("auto");
  EXPECT_EQ(a.kind(), EdgeFilter::Kind::automatic);
  EXPECT_EQ(a, EdgeFilter::automatic());
  EXPECT_EQ(a.drop_count(10), 7u);  // documented: its first ladder step, 0.7
}

TEST(EdgeFilter, RejectsBadTextWithTheReason) {
  auto parse = [](const char* s) { return [s] { (void)EdgeFilter::parse(s); }; };
  expect_error_mentioning(parse("-1"), {"negative"}, "-1");
  expect_error_mentioning(parse("1.5"), {"below 1"}, "1.5 as a fraction");
  expect_error_mentioning(parse("abc"), {"abc", "fraction"}, "abc");
  expect_error_mentioning(parse("100%"), {"100%"}, "100%");
  expect_error_mentioning(parse(""), {"fraction"}, "empty");
  expect_error_mentioning(parse("0.7.1"), {}, "two dots");
  expect_error_mentioning(parse("inf"), {}, "infinity");
  expect_error_mentioning([] { (void)EdgeFilter::fraction(1.0); }, {"[0, 1)"}, "fraction 1");
  expect_error_mentioning([] { (void)EdgeFilter::fraction(std::nan("")); }, {}, "fraction NaN");
}

TEST(EdgeFilter, DropCountFloorsTheFractionAndKeepsAtLeastOne) {
  const EdgeFilter f = EdgeFilter::fraction(0.7);
  EXPECT_EQ(f.drop_count(10), 7u);  // floor(7.0)
  EXPECT_EQ(f.drop_count(1000), 700u);
  EXPECT_EQ(f.drop_count(3), 2u);  // floor(2.1)
  EXPECT_EQ(f.drop_count(1), 0u);  // the only solution is kept
  EXPECT_EQ(f.drop_count(0), 0u);
  EXPECT_EQ(EdgeFilter::fraction(0.999).drop_count(2), 1u);  // floor(1.998) = 1, keeps 1
  const EdgeFilter c = EdgeFilter::count(1000);
  EXPECT_EQ(c.drop_count(5000), 1000u);
  EXPECT_EQ(c.drop_count(1000), 999u);  // would drop all: keeps one
  EXPECT_EQ(c.drop_count(10), 9u);
  EXPECT_EQ(c.drop_count(1), 0u);
  EXPECT_EQ(c.drop_count(0), 0u);
}

TEST(EdgeFilter, ToStringRoundTrips) {
  for (const EdgeFilter& f :
       {EdgeFilter(), EdgeFilter::fraction(0.7), EdgeFilter::fraction(0.5), EdgeFilter::count(1000),
        EdgeFilter::count(0), EdgeFilter::automatic()})
    EXPECT_EQ(EdgeFilter::parse(f.to_string()), f) << f.to_string();
}

TEST(EdgeFilter, ParsesPercentagesAndCountsOnlyInTheirOwnSpelling) {
  EXPECT_EQ(EdgeFilter::parse("12.5%"), EdgeFilter::fraction(0.125));
  EXPECT_EQ(EdgeFilter::parse("0%"), EdgeFilter::fraction(0));
  EXPECT_EQ(EdgeFilter::parse("0.999"), EdgeFilter::fraction(0.999));
  // An integer is a count however large; with a point or an exponent it is a fraction, so 1e3
  // and 1000.0 are fractions >= 1, refused, not read as the count 1000.
  EXPECT_EQ(EdgeFilter::parse("250000"), EdgeFilter::count(250000));
  for (const char* bad : {"1e3", "1000.0", "1.0"}) {
    expect_error_mentioning([bad] { (void)EdgeFilter::parse(bad); }, {bad, "below 1"}, bad);
  }
  // Only the exact words: no spaces, signs or other case.
  for (const char* bad : {" 0.7", "0.7 ", "+0.7", "AUTO", "Auto", "None", "70 %", "%", "nan"}) {
    expect_error_mentioning([bad] { (void)EdgeFilter::parse(bad); }, {"auto", "none"}, bad);
  }
}

TEST(EdgeFilter, AutoStartsAtTheFirstStepOfAnIncreasingLadderBelowOne) {
  const EdgeFilter a = EdgeFilter::automatic();
  EXPECT_EQ(a.kind(), EdgeFilter::Kind::automatic);
  EXPECT_EQ(a.value(), EdgeFilter::kAutoLadder[0]);
  EXPECT_EQ(a.to_string(), "auto");
  double previous = 0;
  for (double f : EdgeFilter::kAutoLadder) {
    EXPECT_GT(f, previous);  // "the smallest fraction that ..." needs an increasing ladder
    EXPECT_LT(f, 1.0);       // and each step keeps some partial solutions
    previous = f;
  }
  // Its drop count is the first step's: floor(0.7 L), keeping one.
  EXPECT_EQ(a.drop_count(1000), 700u);
  EXPECT_EQ(a.drop_count(1), 0u);
  // Equality sees the kind: the fraction 0.7 is not "auto".
  EXPECT_NE(a, EdgeFilter::fraction(0.7));
}

// --- EdgeBands ---

TEST(EdgeBands, TheBandsAreTheSamplesWithin20nmOfEitherEnd) {
  // On the default grid (380..780 nm at 5 nm): 380..400 and 760..780 nm, both ends included.
  const WavelengthGrid grid;
  std::vector<double> nm(grid.size());
  for (std::size_t i = 0; i < nm.size(); ++i) nm[i] = grid[i];
  const EdgeBands bands(nm);
  std::vector<std::size_t> want;
  for (std::size_t i = 0; i < nm.size(); ++i)
    if (nm[i] <= 400.0 || nm[i] >= 760.0) want.push_back(i);
  EXPECT_EQ(want.size(), 10u);
  EXPECT_EQ(bands.edge_samples(), want);
  // On a 7 nm grid from 400 nm: 400, 407, 414 and the three below its end.
  const std::vector<double> odd = wavelengths(400, 701, 7);
  const EdgeBands seven(odd);
  const std::size_t n = odd.size();
  EXPECT_EQ(seven.edge_samples(), (std::vector<std::size_t>{0, 1, 2, n - 3, n - 2, n - 1}));
}

TEST(EdgeBands, APeakIsAnEdgeSampleAboveTheMeanOver400To700nm) {
  const std::vector<double> nm = wavelengths(380, 780, 5);
  const EdgeBands bands(nm);
  // The interior mean is the mean of the samples at 400..700 nm (the test's own sum).
  std::vector<double> s(nm.size());
  for (std::size_t i = 0; i < s.size(); ++i) s[i] = 0.2 + 0.001 * static_cast<double>(i * i % 17);
  double sum = 0;
  int count = 0;
  for (std::size_t i = 0; i < nm.size(); ++i)
    if (nm[i] >= 400 && nm[i] <= 700) sum += s[i], ++count;
  const double mean = sum / count;
  EXPECT_EQ(count, 61);
  EXPECT_NEAR(bands.interior_mean(s), mean, 1e-15);
  // Flat: every edge sample equals the mean, which is not above it.
  const std::vector<double> flat(nm.size(), 0.5);
  EXPECT_TRUE(bands.free_of_peaks(flat));
  EXPECT_DOUBLE_EQ(bands.edge_ratio(flat), 1.0);
  // A sample at 780 nm (an edge) a little above the mean is a peak; at 705 nm (outside both the
  // bands and the interior) any height is not.
  for (double height : {1.01, 3.0}) {
    std::vector<double> peak = flat;
    peak.back() = height * 0.5;
    EXPECT_FALSE(bands.free_of_peaks(peak)) << height;
    EXPECT_NEAR(bands.edge_ratio(peak), height, 1e-12);
  }
  std::vector<double> inner = flat;
  inner[65] = 100.0;  // 705 nm
  EXPECT_TRUE(bands.free_of_peaks(inner));
  // 400 nm is both an edge sample and in the interior.
  std::vector<double> at400 = flat;
  at400[4] = 0.6;
  EXPECT_FALSE(bands.free_of_peaks(at400));
  EXPECT_NEAR(bands.interior_mean(at400), 0.5 + 0.1 / 61, 1e-15);
}

TEST(EdgeBands, AGridOutside400To700nmMeasuresAgainstItsOwnMiddle) {
  // 720..800 nm: the interior is every sample outside the bands (745..775 nm).
  const std::vector<double> nm = wavelengths(720, 800, 5);
  const EdgeBands bands(nm);
  std::vector<double> s(nm.size());
  std::iota(s.begin(), s.end(), 1.0);  // 1, 2, ... 17
  EXPECT_EQ(bands.edge_samples(), (std::vector<std::size_t>{0, 1, 2, 3, 4, 12, 13, 14, 15, 16}));
  EXPECT_DOUBLE_EQ(bands.interior_mean(s), (6.0 + 7 + 8 + 9 + 10 + 11 + 12) / 7);
  EXPECT_FALSE(bands.free_of_peaks(s));  // 13..17 at the red end exceed 9
  EXPECT_DOUBLE_EQ(bands.edge_ratio(s), 17.0 / 9.0);
}

TEST(EdgeBands, NoInteriorOrNoBandsMeansNoPeaks) {
  // 300..330 nm: every sample is within 20 nm of an end and none is in 400..700 nm.
  const EdgeBands narrow(wavelengths(300, 330, 5));
  const std::vector<double> spiky = {9, 0, 0, 0, 0, 0, 9};
  EXPECT_TRUE(narrow.free_of_peaks(spiky));
  EXPECT_EQ(narrow.interior_mean(spiky), 0.0);
  EXPECT_EQ(narrow.edge_ratio(spiky), 0.0);
  // No bands at all (the default, or no wavelengths).
  for (const EdgeBands& none : {EdgeBands(), EdgeBands(std::vector<double>{})}) {
    EXPECT_TRUE(none.edge_samples().empty());
    EXPECT_TRUE(none.free_of_peaks(spiky));
  }
  // A zero interior: the ratio is 0, not a division by zero.
  const EdgeBands bands(wavelengths(380, 780, 5));
  std::vector<double> dark(81, 0.0);
  dark[0] = 1.0;
  EXPECT_EQ(bands.edge_ratio(dark), 0.0);
  EXPECT_FALSE(bands.free_of_peaks(dark));
}

}  // namespace
}  // namespace spectralize
