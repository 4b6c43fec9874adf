#pragma once
// Renders of one scene by several sets of spectra on shared paths: every render evaluates the
// same path records (paths.h) with its own textures at its own wavelengths, and the film
// accumulates CIE XYZ per pixel (the mean over samples, box filter). Differences between renders
// are then due to their spectra and wavelength sampling only.

#include <span>
#include <string>
#include <vector>

#include "path_tracer/environment.h"
#include "path_tracer/paths.h"
#include "path_tracer/scene.h"
#include "path_tracer/spectral_texture.h"
#include "path_tracer/wavelengths.h"
#include "spectralize/core/xyz.h"

namespace spectralize::path_tracer {

/// One way to make the scene spectral.
struct SpectralRender {
  std::string name;
  const SpectralTexture* surface = nullptr;  // the surfaces' reflectances, by texel
  const SpectralTexture* light = nullptr;    // the environment's radiance, by texel
  bool dense = false;  // all reference wavelengths per path (else one hero packet)
};

/// XYZ images of each render after each requested number of samples per pixel.
struct RenderResult {
  int size = 0;
  std::vector<int> spp;                               // increasing
  std::vector<std::vector<std::vector<Xyz>>> images;  // [render][spp index][y * size + x]
  std::vector<float> coverage;  // per pixel: the fraction of camera rays that met a surface
};

/// Renders size x size pixels with max(spp) samples each, keeping the images after each count
/// in `spp`, on `threads` threads (rows split between them; the result does not depend on the
/// count). Throws Error for an empty or non-increasing spp list, a size < 1, or a render
/// without textures. Cost: O(size^2 max(spp) (rays + packets x vertices)).
RenderResult render(const Scene& scene, const Environment& environment, const SpectralFilm& film,
                    std::span<const SpectralRender> renders, int size, std::vector<int> spp,
                    int threads);

/// The XYZ of one path under one render's spectra at `packets`. Cost: O(packets x vertices).
Xyz evaluate_path(const PathRecord& path, const SpectralRender& render,
                  std::span<const WavelengthPacket> packets);

}  // namespace spectralize::path_tracer
