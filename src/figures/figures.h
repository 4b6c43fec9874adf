#pragma once
// `spectralize_figures figures OUTDIR`: the paper's figures (the light's and the surface's
// spectra, the half-RGB, half-spectral spheres) and the same sphere under illuminants A and
// FL11, with the CIEDE2000 between the halves printed and mapped.

#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

namespace spectralize::figures {

/// What a sphere figure measured between its halves.
struct SphereFigure {
  std::string name;        // file stem, e.g. "fig4_sphere_surface"
  std::string light;       // e.g. "D65"
  double max_delta_e = 0;  // CIEDE2000 over mirror pixel pairs
  double mean_delta_e = 0;
  std::size_t pairs = 0;
};

/// Side of the sphere images and their supersampling (the difference maps are
/// kSphereSize x delta_e_map_height(kSphereSize)).
inline constexpr int kSphereSize = 512;
inline constexpr int kSphereSupersample = 4;
/// CIEDE2000 at the bright end of every difference map's colour bar.
inline constexpr double kDeltaEMapScale = 10.0;

/// Writes fig1..fig6 (PNG) and their difference maps into `outdir` (created if missing), prints
/// one line per sphere ("NAME: max dE2000 V ...") to `out`. Throws Error naming the file and the
/// reason. Cost: ~1 s (4 renders of 512^2 x 81 bands, two plots).
std::vector<SphereFigure> make_figures(const std::string& outdir, std::ostream& out);

}  // namespace spectralize::figures
