// The exact table built in the core (docs/DESIGN.md §14): lazily, cell by cell, every colour
// of the gamut gets a blend that reproduces it (the test's own integration) within the bounds;
// stored nodes are checked before use (the table built whole, as a file, is in
// table_file_test.cpp).

#include <gtest/gtest.h>

#include <random>

#include "core/tables/exact_table.h"
#include "test_support.h"

namespace spectralize {
namespace {

using test::frame_of;

Xyz integrate(const Spectralizer& sp, const std::vector<float>& v) {
  const std::vector<double> d(v.begin(), v.end());
  return test::reference_xyz(sp.settings().grid, d, Observer::get(sp.settings().observer),
                             sp.illuminant() ? &sp.illuminant()->spd : nullptr);
}

// A coarse table (fast to build) is as exact as the default one.
const TableResolution kCoarse{6, 2, 24};

TEST(ExactTable, LazyBlendsReproduceEveryColourOfTheGamut) {
  for (Mode mode : {Mode::reflectance, Mode::emission}) {
    SCOPED_TRACE(std::string(to_string(mode)));
    SpectralizerSettings s;
    s.mode = mode;
    const Spectralizer sp(s);
    ExactTable table(sp, frame_of(test::kRec2020ToXyz), kCoarse);
    std::mt19937 rng(12);
    std::uniform_real_distribution<double> u(-0.3, 1.3);
    const std::size_t n = s.grid.size();
    int inside = 0, outside = 0;
    double worst = 0;
    std::vector<float> out(n);
    for (int k = 0; k < 3000; ++k) {
      const Xyz t = mul(table.target_from_rgb(), Xyz{u(rng), u(rng), u(rng)});
      TableBlend b;
      if (!table.locate(t, b)) {
        ++outside;
        if (t.Y > 0) {
          EXPECT_FALSE(sp.in_gamut(t) && sp.gamut().contains((1 + 1e-6) * t));
        }
        continue;
      }
      ++inside;
      table.blend_into(b, out.data());
      for (float v : out) {
        ASSERT_GE(v, 0.0f);
        if (mode == Mode::reflectance) {
          ASSERT_LE(v, 1.0f);
        }
      }
      worst = std::max(worst, test::rel_err(integrate(sp, out), t));
    }
    std::printf("  %s: %d inside (worst relative XYZ %.2g), %d outside; %llu boundary cells\n",
                std::string(to_string(mode)).c_str(), inside, worst, outside,
                static_cast<unsigned long long>(table.stats().boundary_cells));
    EXPECT_GT(inside, 500);
    EXPECT_GT(table.stats().boundary_cells, 0u);
    EXPECT_LE(worst, 1e-5);
  }
}

TEST(ExactTable, StoredNodesAreCheckedAgainstTheirColour) {
  SpectralizerSettings s;
  s.mode = Mode::reflectance;
  const Spectralizer sp(s);
  ExactTable made(sp, frame_of(test::kRec709ToXyz), kCoarse);
  made.build();
  std::vector<std::pair<std::size_t, std::vector<float>>> solved;
  made.for_each_solved_node([&](std::size_t i, std::span<const float> v) {
    solved.emplace_back(i, std::vector<float>(v.begin(), v.end()));
  });
  ASSERT_GT(solved.size(), 50u);
  ExactTable fresh(sp, frame_of(test::kRec709ToXyz), kCoarse);
  auto [index, values] = solved[solved.size() / 2];
  std::vector<float> wrong = values;
  wrong[40] *= 0.9f;
  EXPECT_FALSE(fresh.adopt_node(index, wrong));  // not its colour
  std::vector<float> over = values;
  over[3] = 1.5f;
  EXPECT_FALSE(fresh.adopt_node(index, over));                    // above the bound
  EXPECT_FALSE(fresh.adopt_node(made.node_count() + 5, values));  // no such node
  EXPECT_TRUE(fresh.adopt_node(index, values));
  EXPECT_EQ(fresh.stats().nodes_loaded, 1u);
  EXPECT_FALSE(fresh.dirty());
}

TEST(ExactTable, SnappedWhiteMakesWhiteTheSolidsVertex) {
  Mat3 m = frame_of(test::kRec709ToXyz);
  for (double& v : m) v *= 1 + 3e-7;  // a float measurement through OCIO
  const Mat3 snapped = snap_frame_white(m);
  const Xyz w = mul(snapped, Xyz{1, 1, 1});
  EXPECT_NEAR(w.X, kWhiteD65.X, 1e-15);
  EXPECT_NEAR(w.Y, kWhiteD65.Y, 1e-15);
  EXPECT_NEAR(w.Z, kWhiteD65.Z, 1e-15);
  Mat3 far = m;
  far[0] *= 1.01;  // not D65: left alone
  EXPECT_EQ(snap_frame_white(far), far);
}

}  // namespace
}  // namespace spectralize
