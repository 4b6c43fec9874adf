// The model registry (src/core/models/model_registry.cpp, docs/DESIGN.md §6): the four models in
// the order --help lists them, the default one, the settings each reads (the paper model the
// filter, the smooth model the curvature, the natural and exemplar models none), unknown names
// refused naming the valid ones, and each entry builds its own model: exact and bounded
// (test_support.h's integration), with that model's own details.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "spectralize/core/sample_weights.h"
#include "spectralize/core/spectrum_model.h"
#include "test_support.h"

namespace spectralize {
namespace {

TEST(ModelRegistry, ListsTheFourModelsWithTheDefaultFirst) {
  std::vector<std::string> names;
  for (const ModelInfo& m : spectrum_models()) {
    names.emplace_back(m.name);
    EXPECT_FALSE(m.summary.empty()) << m.name;
    EXPECT_TRUE(static_cast<bool>(m.make)) << m.name;
    EXPECT_EQ(&find_model(m.name), &m);
  }
  EXPECT_EQ(names, (std::vector<std::string>{"exemplar", "natural", "smooth", "paper"}));
  EXPECT_EQ(default_model_name(), "exemplar");
}

TEST(ModelRegistry, EachModelReadsOnlyItsOwnSettings) {
  for (const ModelInfo& m : spectrum_models()) {
    SCOPED_TRACE(std::string(m.name));
    EXPECT_EQ(m.uses("filter"), m.name == "paper");
    EXPECT_EQ(m.uses("curvature"), m.name == "smooth");
    EXPECT_FALSE(m.uses("observer"));  // shared settings are not the model's own
    EXPECT_FALSE(m.uses(""));
  }
}

TEST(ModelRegistry, UnknownNamesAreRefusedNamingTheValidOnes) {
  for (const char* bad : {"Paper", "smoth", "", "natural "}) {
    test::expect_error_mentioning([bad] { (void)find_model(bad); },
                                  {"exemplar", "natural", "smooth", "paper"}, bad);
  }
  test::expect_error_mentioning([] { (void)find_model("jakob"); }, {"jakob"}, "jakob");
}

TEST(ModelRegistry, EachEntryBuildsItsOwnModel) {
  // On the default grid, reflectance under D65: a mid grey and a bluish colour are exact
  // (1e-12) and within [0, 1] for every model.
  const WavelengthGrid grid;
  const Illuminant d65 = Illuminant::get("D65");
  const Observer& obs = Observer::get("cie1931");
  const SampleWeights w(grid, obs, &d65);
  std::vector<double> nm;
  for (std::size_t i = 0; i < grid.size(); ++i) nm.push_back(grid[i]);
  ModelContext c;
  c.columns = w.columns();
  c.wavelengths = nm;
  c.step_nm = grid.step();
  // A detail only that model reports (model_registry.cpp's entries build the model of their
  // name): the exemplar model counts exemplars, the natural model its fallback weight (and no
  // exemplars), the smooth model its primal phase, the paper model its admissible solutions.
  const std::vector<std::pair<std::string, std::string>> own_detail = {
      {"exemplar", "exemplars"},
      {"natural", "fallback_weight"},
      {"smooth", "primal_phase"},
      {"paper", "admissible"}};
  for (const auto& [name, detail] : own_detail) {
    SCOPED_TRACE(name);
    const auto model = find_model(name).make(c);
    ASSERT_NE(model, nullptr);
    for (double tilt : {0.0, 0.4}) {
      std::vector<double> rho(grid.size());
      for (std::size_t i = 0; i < rho.size(); ++i)
        rho[i] = 0.45 - tilt * (static_cast<double>(i) / 80.0 - 0.5);
      const Xyz t = test::reference_xyz(grid, rho, obs, &d65.spd);
      const ModelSolution s = model->solve(t, 1.0);
      ASSERT_TRUE(s.converged);
      EXPECT_LE(test::rel_err(test::reference_xyz(grid, s.values, obs, &d65.spd), t), 1e-12);
      for (double v : s.values) {
        EXPECT_GE(v, 0.0);
        EXPECT_LE(v, 1.0);
      }
      for (const auto& [other, other_detail] : own_detail) {
        bool has = false;
        for (const ModelDetail& d : s.details) has |= d.name == other_detail;
        // The exemplar model extends the natural one: it reports its fallback weight too.
        const bool expected = other == name || (name == "exemplar" && other == "natural");
        EXPECT_EQ(has, expected) << other_detail;
      }
    }
  }
}

}  // namespace
}  // namespace spectralize
