#pragma once
// Arrays of colours to spectra and back (docs/DESIGN.md §13): the image kernel without an
// image, for the Python module and C++ callers. Colours go through OCIO to XYZ and through the
// shared node table (and its persistent cache) exactly as pixels do; spectra come back through
// the reference integration and OCIO as --to-rgb does.

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "colour/colour_space.h"
#include "pipeline/job_log.h"
#include "pipeline/job_plan.h"
#include "pipeline/rgb_from_spectral.h"
#include "pipeline/spectral_converter.h"
#include "pipeline/table_pool.h"
#include "settings/settings.h"

namespace spectralize {

class ColourArrays {
 public:
  /// For the colours `plan` (plan_colours of colours: colour space and mode resolved) says:
  /// takes the spectralizer and table for them from `pool` (loading settings.cache_dir). A data
  /// colour space's values are taken as CIE XYZ, as an image's are (warnings()). Cost: the first
  /// time, the table's setup.
  ColourArrays(const JobPlan& plan, TablePool& pool, const LogFn& log);

  /// The settings as used (colour space and mode resolved). Cost: O(1).
  const Settings& settings() const { return settings_; }
  /// What the plan warned about (a data colour space), for the caller to show on each use.
  /// Cost: O(1).
  const std::vector<std::string>& warnings() const { return warnings_; }
  /// Samples per spectrum. Cost: O(1).
  std::size_t bands() const { return settings_.spectral.grid.size(); }

  /// n packed RGB triples to n spectra of bands() floats each, in parallel on OIIO's pool
  /// (settings.threads); every colour counted by kind, its error measured on the float
  /// samples. Thread-safe. Cost: O(n x bands), plus node solves on first use.
  PixelCounts spectra(const float* rgb, std::size_t n, float* out) const;

 private:
  Settings settings_;
  std::vector<std::string> warnings_;
  std::shared_ptr<const ColourSpaces> spaces_;
  TablePool::Entry* entry_ = nullptr;
  ColourTransform to_xyz_;
};

/// n spectra of wavelengths.size() floats each (sample i at wavelengths[i] nm) to n packed RGB
/// triples in settings.colorspace (or settings.display and view): emission integrated with the
/// observer, reflectance under settings.spectral.illuminant (white balanced unless as_lit).
/// `plan` (plan_colours of spectra) says which by its mode. Throws Error (starting with
/// `where`) for bad wavelengths. Cost: O(n x bands).
RgbCounts rgb_of_spectra(const float* spectra, std::size_t n,
                         const std::vector<double>& wavelengths, const JobPlan& plan, float* rgb,
                         const std::string& where);

}  // namespace spectralize
