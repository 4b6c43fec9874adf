// Colour differences of images: zero for equal images, the CIEDE2000 of the pair otherwise, and
// the nearest-rank statistics over the chosen pixels.

#include "path_tracer/image_difference.h"

#include <gtest/gtest.h>

#include "../test_support.h"
#include "core/colorimetry/colour_difference.h"

namespace spectralize::path_tracer {
namespace {

TEST(ImageDifference, PerPixelCiede2000) {
  const Xyz white{0.95, 1, 1.09};
  const std::vector<Xyz> a{{0.2, 0.2, 0.2}, {0.5, 0.4, 0.1}};
  const std::vector<Xyz> b{{0.2, 0.2, 0.2}, {0.45, 0.4, 0.12}};
  const std::vector<double> de = delta_e_map(a, b, white);
  EXPECT_EQ(de[0], 0.0);
  EXPECT_DOUBLE_EQ(de[1], delta_e_2000(to_lab(a[1], white), to_lab(b[1], white)));
  EXPECT_GT(de[1], 1.0);
  test::expect_error_mentioning([&] { delta_e_map(a, {b[0]}, white); }, {"2", "1 pixels"}, "sizes");
}

TEST(ImageDifference, NearestRankStatistics) {
  std::vector<double> v;
  for (int i = 100; i >= 1; --i) v.push_back(i);  // 1..100, unsorted
  const DeltaEStats s = summarize(v);
  EXPECT_EQ(s.pixels, 100u);
  EXPECT_DOUBLE_EQ(s.mean, 50.5);
  EXPECT_DOUBLE_EQ(s.p95, 95);
  EXPECT_DOUBLE_EQ(s.max, 100);
  // Only the masked pixels count: the values 1..10 (stored at the end).
  std::vector<bool> mask(100, false);
  for (int i = 90; i < 100; ++i) mask[i] = true;
  const DeltaEStats m = summarize(v, mask);
  EXPECT_EQ(m.pixels, 10u);
  EXPECT_DOUBLE_EQ(m.mean, 5.5);
  EXPECT_DOUBLE_EQ(m.p95, 10);
  EXPECT_EQ(summarize({}, {}).pixels, 0u);
}

}  // namespace
}  // namespace spectralize::path_tracer
