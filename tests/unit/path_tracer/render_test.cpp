// Renders on shared paths: a path record evaluates to the sum of its light terms times the
// reflectances before them (sums written out here), the film is independent of the thread count,
// and a hero-wavelength render converges to the dense render of the same spectra as 1/sqrt(spp).

#include "path_tracer/render.h"

#include <gtest/gtest.h>

#include "../test_support.h"
#include "path_tracer/image_difference.h"
#include "path_tracer/sampled_spectra.h"

namespace spectralize::path_tracer {
namespace {

// Spectra on 360..830 nm at 10 nm (48 bands): texel t is a ramp, a bump or a constant.
SampledSpectra test_spectra(std::size_t texels, float scale_light) {
  const std::size_t bands = 48;
  std::vector<float> s;
  for (std::size_t b = 0; b < bands; ++b) s.push_back(0.1f + 0.8f * b / (bands - 1));  // ramp
  for (std::size_t b = 0; b < bands; ++b) {
    const float x = (static_cast<float>(b) - 20) / 6;
    s.push_back(0.05f + 0.9f * std::exp(-x * x));  // bump at 560 nm
  }
  for (std::size_t b = 0; b < bands; ++b) s.push_back(0.5f);
  std::vector<std::uint32_t> index(texels);
  for (std::size_t t = 0; t < texels; ++t) index[t] = static_cast<std::uint32_t>(t % 3);
  return SampledSpectra(360, 10, bands, std::move(s), std::move(index),
                        std::vector<float>(texels, scale_light));
}

TEST(Render, PathIsItsLightTermsTimesTheReflectancesBeforeThem) {
  const Observer& obs = Observer::get("cie1931");
  const SpectralFilm film(obs);
  // Constant spectra: reflectance 0.5 everywhere, light 2 everywhere (the constant, index 2).
  const SampledSpectra surface(360, 470, 2, {0.5f, 0.5f}, {0, 0, 0});
  const SampledSpectra light(360, 470, 2, {2.0f, 2.0f}, {0, 0});
  PathRecord path;
  path.vertices = 2;
  path.vertex_texel = {1, 2, 0};
  path.terms[0] = {0, 1, 0.75f};  // after vertex 0: 0.75 * 2 * 0.5
  path.terms[1] = {1, 2, 0.25f};  // after vertex 1: 0.25 * 2 * 0.25
  path.term_count = 2;
  const SpectralRender r{"const", &surface, &light, true};
  const Xyz got = evaluate_path(path, r, film.reference());
  // A constant spectrum 1 has XYZ = (sum tau cmf) / K, the test's own sums.
  Xyz unit;
  for (int nm = 360; nm <= 830; ++nm) {
    const std::size_t k = static_cast<std::size_t>(nm - 360);
    const double tau = (nm == 360 || nm == 830) ? 0.5 : 1.0;
    unit = unit + (tau / test::y_integral(obs)) * Xyz{obs.cmf[0][k], obs.cmf[1][k], obs.cmf[2][k]};
  }
  const Xyz want = (0.75 * 2 * 0.5 + 0.25 * 2 * 0.25) * unit;
  EXPECT_LT(test::rel_err(got, want), 1e-6);
}

struct Fixture {
  Fixture()
      : scene(SceneLayout{}, 12, 8),
        environment(8, 4, std::vector<Xyz>(32, Xyz{0.95, 1, 1.09})),
        film(Observer::get("cie1931")),
        surface(test_spectra(96, 1)),
        light(test_spectra(32, 1.5f)) {}
  Scene scene;
  Environment environment;
  SpectralFilm film;
  SampledSpectra surface, light;
};

TEST(Render, ImagesDoNotDependOnTheThreadCount) {
  const Fixture f;
  const SpectralRender r[] = {{"hero", &f.surface, &f.light, false}};
  const RenderResult one = render(f.scene, f.environment, f.film, r, 12, {2, 5}, 1);
  const RenderResult two = render(f.scene, f.environment, f.film, r, 12, {2, 5}, 2);
  ASSERT_EQ(one.images[0].size(), 2u);
  for (std::size_t k = 0; k < 2; ++k)
    for (std::size_t i = 0; i < one.images[0][k].size(); ++i) {
      ASSERT_EQ(one.images[0][k][i], two.images[0][k][i]) << k << " " << i;
    }
  EXPECT_EQ(one.coverage, two.coverage);
}

TEST(Render, HeroWavelengthsConvergeToTheDenseRenderAsOneOverRootSpp) {
  const Fixture f;
  const SpectralRender r[] = {{"hero", &f.surface, &f.light, false},
                              {"dense", &f.surface, &f.light, true}};
  const RenderResult res = render(f.scene, f.environment, f.film, r, 16, {16, 256}, 2);
  const Xyz white = f.environment.white_up();
  const double coarse = summarize(delta_e_map(res.images[0][0], res.images[1][0], white)).mean;
  const double fine = summarize(delta_e_map(res.images[0][1], res.images[1][1], white)).mean;
  // 16 times the samples: a quarter of the error (the noise of 256 pixels' means: +-20%).
  EXPECT_GT(coarse / fine, 4 * 0.8) << coarse << " " << fine;
  EXPECT_LT(coarse / fine, 4 * 1.25) << coarse << " " << fine;
}

TEST(Render, RefusesBadSampleCounts) {
  const Fixture f;
  const SpectralRender r[] = {{"hero", &f.surface, &f.light, false}};
  auto repeated = [&] { render(f.scene, f.environment, f.film, r, 4, {4, 4}, 1); };
  test::expect_error_mentioning(repeated, {"increasing"}, "repeated");
  test::expect_error_mentioning([&] { render(f.scene, f.environment, f.film, r, 4, {}, 1); },
                                {"increasing"}, "empty");
  const SpectralRender none[] = {{"none", nullptr, &f.light, false}};
  test::expect_error_mentioning([&] { render(f.scene, f.environment, f.film, none, 4, {1}, 1); },
                                {"none", "no textures"}, "textures");
}

}  // namespace
}  // namespace spectralize::path_tracer
