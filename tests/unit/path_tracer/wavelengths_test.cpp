// The film's wavelengths: the visible pdf is a density on 360..830 nm and sample_visible its
// inverse CDF (both checked by the test's own numerical integration), the hero packet rotates by
// quarters, the hero estimator's mean is the integral of the spectrum against the matching
// functions, and the dense packets are the 1 nm trapezoid rule of docs/DESIGN.md §3.

#include "path_tracer/wavelengths.h"

#include <gtest/gtest.h>

#include <cmath>

#include "../test_support.h"

namespace spectralize::path_tracer {
namespace {

// The test's integral of the pdf from 360 nm to nm (midpoint rule, 0.001 nm).
double cdf(double nm) {
  double s = 0;
  const double h = 0.001;
  for (double l = 360 + h / 2; l < nm; l += h) s += SpectralFilm::visible_pdf(l) * h;
  return s;
}

// A smooth test spectrum that is not a combination of the matching functions.
double test_spectrum(double nm) {
  return 0.55 + 0.4 * std::sin(nm / 37.0) * std::cos(nm / 91.0);
}

TEST(SpectralFilm, VisiblePdfIsADensityOn360To830) {
  EXPECT_NEAR(cdf(830), 1.0, 1e-6);
  EXPECT_EQ(SpectralFilm::visible_pdf(359.9), 0.0);
  EXPECT_EQ(SpectralFilm::visible_pdf(830.1), 0.0);
  // Its peak is at 538 nm.
  EXPECT_GT(SpectralFilm::visible_pdf(538), SpectralFilm::visible_pdf(500));
  EXPECT_GT(SpectralFilm::visible_pdf(538), SpectralFilm::visible_pdf(580));
}

TEST(SpectralFilm, SampleVisibleIsTheInverseCdf) {
  for (const double u : {0.0, 0.01, 0.2, 0.5, 0.77, 0.999}) {
    const double nm = SpectralFilm::sample_visible(u);
    EXPECT_NEAR(cdf(nm), u, 1e-6) << u;
  }
  EXPECT_NEAR(SpectralFilm::sample_visible(0.0), 360.0, 1e-9);
}

TEST(SpectralFilm, HeroPacketRotatesByQuarters) {
  const SpectralFilm film(Observer::get("cie1931"));
  const WavelengthPacket p = film.hero(0.6);
  for (int i = 0; i < kLanes; ++i) {
    const double want = std::fmod(0.6 + i / 4.0, 1.0);
    EXPECT_NEAR(cdf(p.nm[i]), want, 1e-5) << i;
  }
}

TEST(SpectralFilm, HeroEstimatorMeanIsTheIntegralAgainstTheMatchingFunctions) {
  const Observer& obs = Observer::get("cie1931");
  const SpectralFilm film(obs);
  const double k = test::y_integral(obs);
  // The expectation: integral of f times the matching functions (linear between the 1 nm table
  // points) over 360..830, / K, by the test's midpoint rule at 0.01 nm.
  Xyz want;
  for (double l = 360.005; l < 830; l += 0.01) {
    const std::size_t j = static_cast<std::size_t>(l - 360);
    const double f = l - 360 - static_cast<double>(j);
    const double v = test_spectrum(l) * 0.01 / k;
    want.X += v * ((1 - f) * obs.cmf[0][j] + f * obs.cmf[0][j + 1]);
    want.Y += v * ((1 - f) * obs.cmf[1][j] + f * obs.cmf[1][j + 1]);
    want.Z += v * ((1 - f) * obs.cmf[2][j] + f * obs.cmf[2][j + 1]);
  }
  // The estimator averaged over offsets u on a fine stratified grid (its mean over u).
  Xyz got;
  const int m = 40000;
  for (int s = 0; s < m; ++s) {
    const WavelengthPacket p = film.hero((s + 0.5) / m);
    for (int i = 0; i < kLanes; ++i) {
      const double f = test_spectrum(p.nm[i]) / m;
      got = got + f * Xyz{p.xyz_weight[0][i], p.xyz_weight[1][i], p.xyz_weight[2][i]};
    }
  }
  EXPECT_LT(test::rel_err(got, want), 2e-5);
}

TEST(SpectralFilm, DensePacketsAreTheTrapezoidRule) {
  const Observer& obs = Observer::get("cie1931");
  const SpectralFilm film(obs);
  ASSERT_EQ(film.reference().size(), 118u);  // 471 wavelengths in fours
  Xyz got, want, ones;
  for (const WavelengthPacket& p : film.reference())
    for (int i = 0; i < kLanes; ++i) {
      const Xyz w{p.xyz_weight[0][i], p.xyz_weight[1][i], p.xyz_weight[2][i]};
      got = got + test_spectrum(p.nm[i]) * w;
      ones = ones + w;
    }
  for (int nm = 360; nm <= 830; ++nm) {
    const std::size_t j = static_cast<std::size_t>(nm - 360);
    const double tau = (nm == 360 || nm == 830) ? 0.5 : 1.0;
    const double v = tau * test_spectrum(nm) / test::y_integral(obs);
    want = want + v * Xyz{obs.cmf[0][j], obs.cmf[1][j], obs.cmf[2][j]};
  }
  EXPECT_LT(test::rel_err(got, want), 1e-6);
  // A constant spectrum 1 has Y = 1 in emission units (docs/DESIGN.md §3).
  EXPECT_NEAR(ones.Y, 1.0, 1e-6);
  // The padding lane adds nothing.
  const WavelengthPacket& last = film.reference().back();
  EXPECT_EQ(last.xyz_weight[1][3], 0.0f);
}

TEST(SpectralFilm, MatchingFunctionsInterpolateTheTable) {
  const Observer& obs = Observer::get("cie1931");
  const SpectralFilm film(obs);
  const double k = test::y_integral(obs);
  EXPECT_NEAR(film.cmf(555)[1], obs.cmf[1][195] / k, 1e-12);
  EXPECT_NEAR(film.cmf(555.5)[1], (obs.cmf[1][195] + obs.cmf[1][196]) / (2 * k), 1e-12);
  EXPECT_EQ(film.cmf(359)[1], 0.0);
  EXPECT_EQ(film.cmf(831)[0], 0.0);
}

}  // namespace
}  // namespace spectralize::path_tracer
