// The exact table built in the core (docs/DESIGN.md §14): lazily, cell by cell, every colour
// of the gamut gets a blend that reproduces it (the test's own integration) within the bounds;
// built whole, its file is the same whatever the threads; stored nodes are checked before use.

#include <gtest/gtest.h>

#include <atomic>
#include <random>
#include <thread>

#define SPECTRALIZE_RT_IMPLEMENTATION
#include <spectralize/rt.hpp>

#include "core/exact_table.h"
#include "core/table_file.h"
#include "test_support.h"

namespace spectralize {
namespace {

using test::frame_of;

Xyz integrate(const Spectralizer& sp, const std::vector<float>& v) {
  const std::vector<double> d(v.begin(), v.end());
  return test::reference_xyz(sp.settings().grid, d, Observer::get(sp.settings().observer),
                             sp.illuminant() ? &sp.illuminant()->spd : nullptr);
}

ParallelFor threads(int n) {
  return [n](std::size_t count, const std::function<void(std::size_t, std::size_t)>& body) {
    std::atomic<std::size_t> next{0};
    std::vector<std::thread> pool;
    for (int t = 0; t < n; ++t)
      pool.emplace_back([&] {
        for (std::size_t b; (b = next.fetch_add(37)) < count;) body(b, std::min(count, b + 37));
      });
    for (auto& t : pool) t.join();
  };
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

TEST(ExactTable, TheFileIsTheSameWhateverTheThreadsAndAgreesWithTheCore) {
  SpectralizerSettings s;
  s.mode = Mode::reflectance;
  const Spectralizer sp(s);
  ExactTable one(sp, frame_of(test::kRec709ToXyz), kCoarse),
      two(sp, frame_of(test::kRec709ToXyz), kCoarse);
  one.build(threads(1));
  two.build(threads(3));
  const std::string a = encode_table_file(one, sp, {"Linear Rec.709 (sRGB)", "lin_rec709_scene"});
  const std::string b = encode_table_file(two, sp, {"Linear Rec.709 (sRGB)", "lin_rec709_scene"});
  EXPECT_EQ(a, b);
  // The evaluator reads it, and gives the core's spectra.
  std::vector<std::uint64_t> aligned(a.size() / 8 + 1);
  std::memcpy(aligned.data(), a.data(), a.size());
  spz::TableView view;
  char error[256];
  ASSERT_TRUE(view.open(aligned.data(), a.size(), error, sizeof error)) << error;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-0.5f, 1.5f);
  std::vector<float> core(81), rt(81);
  double worst = 0;
  for (int k = 0; k < 2000; ++k) {
    const float rgb[3] = {u(rng), u(rng), u(rng)};
    spz::Spectrum spec;
    if (view.fetch(rgb, spec) != SPZ_EXACT) continue;
    spz::samples(spec, rt.data());
    TableBlend blend;
    ASSERT_TRUE(one.locate(mul(one.target_from_rgb(), Xyz{rgb[0], rgb[1], rgb[2]}), blend, true));
    one.blend_into(blend, core.data());
    for (int i = 0; i < 81; ++i) worst = std::max(worst, double(std::abs(core[i] - rt[i])));
  }
  EXPECT_LE(worst, 1e-6);
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
