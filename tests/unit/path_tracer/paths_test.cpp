// Path sampling (path_tracer/paths.h): the counter-based numbers are uniform on [0, 1), the
// same for the same (pixel, sample, stream) and unrelated otherwise; a traced path is the same
// whatever else was traced before; a camera ray that misses sees the environment once, at
// depth 0; light terms come in increasing depth, one per vertex at most; and the estimates are
// unbiased: on an open floor under uniform radiance the next-event weight averages 1 (the
// integral of cos / pi over the hemisphere), and in the whole scene (a white furnace) the sum of
// a path's terms averages 1 less at most the share of paths cut at kMaxVertices.

#include "path_tracer/paths.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

namespace spectralize::path_tracer {
namespace {

Environment uniform_environment() {
  return Environment(16, 8, std::vector<Xyz>(16 * 8, Xyz{0.95, 1, 1.09}));
}

// The floor alone: the sphere far below it, where no ray from above the floor goes.
SceneLayout floor_only() {
  SceneLayout l;
  l.sphere_centre = {0, -100, 0};
  l.sphere_radius = 0.01;
  return l;
}

TEST(SampleStream, IsUniformOnTheUnitInterval) {
  // 100000 numbers of one stream: in [0, 1), mean 1/2 and variance 1/12 (standard errors
  // 0.0009 and 0.0003), each tenth of the interval 1/10 of them (standard error 0.001).
  SampleStream s(12345, 6, 1);
  const int n = 100000;
  double sum = 0, squares = 0;
  std::vector<int> bins(10, 0);
  for (int i = 0; i < n; ++i) {
    const double u = s.next();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum += u;
    squares += u * u;
    ++bins[static_cast<std::size_t>(u * 10)];
  }
  const double mean = sum / n;
  EXPECT_NEAR(mean, 0.5, 0.005);
  EXPECT_NEAR(squares / n - mean * mean, 1.0 / 12, 0.002);
  for (int b : bins) EXPECT_NEAR(b / static_cast<double>(n), 0.1, 0.006);
}

TEST(SampleStream, IsTheSameForTheSameCounterAndUnrelatedOtherwise) {
  SampleStream a(7, 3, 1), b(7, 3, 1);
  for (int i = 0; i < 16; ++i) EXPECT_EQ(a.next(), b.next());
  // Neighbouring pixels, samples and streams start elsewhere: the first numbers differ.
  std::set<double> first;
  for (std::uint64_t pixel : {0, 1, 2})
    for (std::uint64_t sample : {0, 1, 2})
      for (std::uint64_t stream : {1, 2}) first.insert(SampleStream(pixel, sample, stream).next());
  EXPECT_EQ(first.size(), 18u);
  // Adjacent pixels' first numbers are not correlated: over 20000 pixels the correlation of
  // u(p) and u(p + 1) is within 4 standard errors (1 / sqrt(n)) of 0.
  const int n = 20000;
  std::vector<double> u(n + 1);
  for (int p = 0; p <= n; ++p) u[p] = SampleStream(p, 0, 1).next() - 0.5;
  double c = 0;
  for (int p = 0; p < n; ++p) c += u[p] * u[p + 1];
  EXPECT_LT(std::abs(c / n * 12), 4 / std::sqrt(n));
}

TEST(WavelengthOffset, IsUniformAndIndependentOfThePathsNumbers) {
  const int n = 50000;
  double sum = 0, corr = 0;
  for (int i = 0; i < n; ++i) {
    const double u = wavelength_offset(static_cast<std::uint64_t>(i), 3);
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    EXPECT_EQ(u, wavelength_offset(static_cast<std::uint64_t>(i), 3));
    sum += u;
    // The path's first number for the same pixel and sample (stream 1) is another number.
    corr += (u - 0.5) * (SampleStream(static_cast<std::uint64_t>(i), 3, 1).next() - 0.5);
  }
  EXPECT_NEAR(sum / n, 0.5, 0.006);
  EXPECT_LT(std::abs(corr / n * 12), 4 / std::sqrt(n));
}

TEST(TracePath, IsTheSameWhateverWasTracedBefore) {
  const Scene scene(SceneLayout{}, 12, 8);
  const Environment env = uniform_environment();
  const PathRecord first = trace_path(scene, env, 20, 30, 64, 5);
  for (int s = 0; s < 50; ++s)
    trace_path(scene, env, s % 64, 40, 64, static_cast<std::uint64_t>(s));
  const PathRecord again = trace_path(scene, env, 20, 30, 64, 5);
  ASSERT_EQ(again.vertices, first.vertices);
  ASSERT_EQ(again.term_count, first.term_count);
  for (int v = 0; v < first.vertices; ++v) EXPECT_EQ(again.vertex_texel[v], first.vertex_texel[v]);
  for (int t = 0; t < first.term_count; ++t) {
    EXPECT_EQ(again.terms[t].texel, first.terms[t].texel);
    EXPECT_EQ(again.terms[t].depth, first.terms[t].depth);
    EXPECT_EQ(again.terms[t].weight, first.terms[t].weight);
  }
  // Another sample of the same pixel is another path (its jitter differs).
  int differ = 0;
  for (std::uint64_t s = 0; s < 8; ++s) {
    const PathRecord p = trace_path(scene, env, 20, 30, 64, 100 + s);
    differ += p.vertices != first.vertices || p.vertex_texel != first.vertex_texel ||
              p.terms[0].weight != first.terms[0].weight;
  }
  EXPECT_GT(differ, 0);
}

TEST(TracePath, ACameraRayThatMissesSeesTheEnvironmentOnceAtDepthZero) {
  // A floor under the camera and nothing else: the top rows look past its far edge.
  const Scene scene(floor_only(), 12, 8);
  // A map with a texel of its own per direction band: the term names the texel looked at.
  std::vector<Xyz> map(16 * 8);
  for (std::size_t i = 0; i < map.size(); ++i) map[i] = {1, 1.0 + i, 1};
  const Environment env(16, 8, map);
  int misses = 0;
  for (int px = 0; px < 64; px += 7)
    for (std::uint64_t s = 0; s < 4; ++s) {
      const PathRecord p = trace_path(scene, env, px, 0, 64, s);
      if (p.vertices != 0) continue;
      ++misses;
      ASSERT_EQ(p.term_count, 1);
      EXPECT_EQ(p.terms[0].depth, 0u);
      EXPECT_EQ(p.terms[0].weight, 1.0f);
      // The camera looks down past the floor's far edge: a texel of the lower half (rows 4..7).
      EXPECT_GE(p.terms[0].texel, 16u * 4);
    }
  EXPECT_GT(misses, 0);
}

TEST(TracePath, TermsFollowTheVerticesInIncreasingDepth) {
  const Scene scene(SceneLayout{}, 12, 8);
  const Environment env = uniform_environment();
  int deep = 0;
  for (int py = 0; py < 64; py += 3)
    for (int px = 0; px < 64; px += 3) {
      const PathRecord p = trace_path(scene, env, px, py, 64, 0);
      ASSERT_LE(p.vertices, kMaxVertices);
      ASSERT_LE(p.term_count, p.vertices + 1);
      deep += p.vertices == kMaxVertices;
      for (int t = 0; t < p.term_count; ++t) {
        const LightTerm& term = p.terms[t];
        if (t > 0) {
          EXPECT_GT(term.depth, p.terms[t - 1].depth);
        }
        EXPECT_LE(static_cast<int>(term.depth), p.vertices);
        EXPECT_GT(term.weight, 0.0f);
        EXPECT_LT(term.texel, 16u * 8);
        // Depth 0 is the environment seen directly: only for a path with no vertex.
        EXPECT_EQ(term.depth == 0, p.vertices == 0);
      }
      for (int v = 0; v < p.vertices; ++v) EXPECT_LT(p.vertex_texel[v], 12u * 8);
    }
  EXPECT_GT(deep, 0);  // interreflections between the sphere and the floor are traced
}

// A point of an open floor under radiance 1 from every direction receives pi (the cosine's
// integral over the hemisphere): rho / pi times that is rho. The next-event weight
// cos / (pi pdf) must average 1, and the bounce leaves the floor for the sky.
TEST(TracePath, NextEventWeightAveragesOneOnAnOpenFloor) {
  const Scene scene(floor_only(), 12, 8);
  const Environment env = uniform_environment();
  double sum = 0;
  int paths = 0;
  for (int py = 0; py < 64; ++py)
    for (int px = 0; px < 64; ++px)
      for (std::uint64_t s = 0; s < 16; ++s) {
        const PathRecord p = trace_path(scene, env, px, py, 64, s);
        ASSERT_LE(p.vertices, 1) << px << ", " << py;  // nothing above the floor to bounce to
        if (p.vertices == 0) continue;                 // past the floor's edge
        ++paths;
        for (int t = 0; t < p.term_count; ++t) {
          EXPECT_EQ(p.terms[t].depth, 1u);
          sum += p.terms[t].weight;
        }
      }
  // The weight 4 cos (pdf 1 / 4 pi) has standard deviation sqrt(5/3) per path: below 0.0075 over
  // the 29000 or more paths on the floor.
  ASSERT_GT(paths, 29000);
  EXPECT_NEAR(sum / paths, 1.0, 0.03);
}

// Under uniform radiance, the next-event weight at a vertex averages the unoccluded share of
// the cosine-weighted hemisphere, and a cosine-distributed bounce hits a surface with the rest
// of it: over the paths with a first vertex, P(a second vertex) = 1 - E[depth-1 weight].
TEST(TracePath, BouncesAreCosineDistributedAsTheLightEstimateAssumes) {
  const Scene scene(SceneLayout{}, 12, 8);
  const Environment env = uniform_environment();
  double sum = 0;
  int paths = 0;
  for (int py = 0; py < 64; ++py)
    for (int px = 0; px < 64; ++px)
      for (std::uint64_t s = 0; s < 256; ++s) {
        const PathRecord p = trace_path(scene, env, px, py, 64, s);
        if (p.vertices == 0) continue;
        ++paths;
        double w1 = 0;
        for (int t = 0; t < p.term_count; ++t)
          if (p.terms[t].depth == 1) w1 += p.terms[t].weight;
        sum += (p.vertices >= 2 ? 1.0 : 0.0) - (1 - w1);
      }
  // Per path the difference has standard deviation about 1.3: 0.0018 over the 500000 or more
  // paths with a vertex.
  ASSERT_GT(paths, 500000);
  EXPECT_NEAR(sum / paths, 0.0, 0.006);
}

// The white furnace: every surface white, radiance 1 everywhere. Each point then has radiance 1
// (what it sees is the sky or a white surface of radiance 1), so the sum of a path's weights
// averages 1 - P(a path is cut after kMaxVertices vertices while its next bounce would hit).
TEST(TracePath, WhiteFurnaceSumsToOneBarTheCutPaths) {
  const Scene scene(SceneLayout{}, 12, 8);
  const Environment env = uniform_environment();
  double sum = 0;
  int paths = 0, cut = 0;
  for (int py = 0; py < 64; py += 2)
    for (int px = 0; px < 64; px += 2)
      for (std::uint64_t s = 0; s < 64; ++s) {
        const PathRecord p = trace_path(scene, env, px, py, 64, s);
        ++paths;
        cut += p.vertices == kMaxVertices;
        for (int t = 0; t < p.term_count; ++t) sum += p.terms[t].weight;
      }
  const double mean = sum / paths, cut_share = static_cast<double>(cut) / paths;
  // 65536 paths, per-path standard deviation below 2: standard error < 0.008.
  EXPECT_LT(mean, 1.0 + 0.03);
  EXPECT_GT(mean, 1.0 - cut_share - 0.03);
}

}  // namespace
}  // namespace spectralize::path_tracer
