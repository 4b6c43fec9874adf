#include "figures/reference_rows.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "baseline/sigmoid_spectrum.h"
#include "core/colorimetry/colour_difference.h"
#include "core/solvers/bounded_projection.h"

namespace spectralize::figures {

namespace {

// The space's linear RGB -> XYZ matrix, read off the transform's images of the primaries (the
// working spaces are linear).
baseline::RgbToXyz matrix_of(const ColourTransform& to_xyz) {
  baseline::RgbToXyz m{};
  for (int c = 0; c < 3; ++c) {
    const Xyz column = to_xyz(c == 0, c == 1, c == 2);
    for (int r = 0; r < 3; ++r) m[r][c] = column[r];
  }
  return m;
}

class Rgb2specFit final : public Reconstruction {
 public:
  explicit Rgb2specFit(const RowContext& context) : fitter_(matrix_of(*context.to_xyz)) {}
  Reconstructed reconstruct(std::size_t, std::size_t, const std::array<double, 3>& rgb,
                            const Xyz&) const override {
    const baseline::SigmoidFit fit = fitter_.fit(rgb);
    return {fitter_.spectrum(fit.polynomial), "ok"};
  }

 private:
  baseline::SigmoidFitter fitter_;
};

class Rgb2specTable final : public Reconstruction {
 public:
  explicit Rgb2specTable(const RowContext& context)
      : fitter_(matrix_of(*context.to_xyz)), table_(fitter_, 64, 2) {}
  Reconstructed reconstruct(std::size_t, std::size_t, const std::array<double, 3>& rgb,
                            const Xyz&) const override {
    // As a renderer: float coefficients from the table, evaluated in float at each wavelength.
    const baseline::SigmoidPolynomial p =
        table_(static_cast<float>(rgb[0]), static_cast<float>(rgb[1]), static_cast<float>(rgb[2]));
    const WavelengthGrid& grid = fitter_.grid();
    std::vector<double> values(grid.size());
    for (std::size_t i = 0; i < grid.size(); ++i) values[i] = p(static_cast<float>(grid[i]));
    return {std::move(values), "ok"};
  }

 private:
  baseline::SigmoidFitter fitter_;
  baseline::SigmoidTable table_;
};

class NearestNeighbour final : public Reconstruction {
 public:
  explicit NearestNeighbour(const RowContext& context) : protocol_(*context.protocol) {
    const Xyz white = protocol_.weights().unit_white();
    for (std::size_t k = 0; k < context.sets->size(); ++k)
      for (std::size_t i = 0; i < (*context.sets)[k].size(); ++i) {
        const MeasuredPatch& p = (*context.sets)[k][i];
        pool_.push_back({k, i, to_lab(protocol_.weights().integrate(p.rho), white), p.rho});
      }
  }

  Reconstructed reconstruct(std::size_t set, std::size_t patch, const std::array<double, 3>&,
                            const Xyz& xyz_d65) const override {
    const Xyz target = protocol_.target_of(xyz_d65);
    const Lab lab = to_lab(target, protocol_.weights().unit_white());
    const Entry* nearest = nullptr;
    double best = std::numeric_limits<double>::infinity();
    for (const Entry& e : pool_) {
      if (e.set == set && e.patch == patch) continue;  // leave the patch itself out
      const double d = delta_e_2000(lab, e.lab);
      if (d < best) best = d, nearest = &e;
    }
    std::vector<double> start = nearest->rho;
    for (double& v : start) v = std::clamp(v, 0.0, 1.0);
    Projection p = project_exact(protocol_.weights().columns(), start, target, 1.0);
    return {std::move(p.values), p.converged ? "ok" : "not_converged"};
  }

 private:
  struct Entry {
    std::size_t set, patch;
    Lab lab;
    std::vector<double> rho;
  };
  const Spectralizer& protocol_;
  std::vector<Entry> pool_;
};

}  // namespace

ValidationConfig nearest_neighbour_row() {
  ValidationConfig c;
  c.name = "nearest neighbour (leave one out, projected to the colour; reference)";
  c.make = [](const RowContext& context) -> std::unique_ptr<Reconstruction> {
    return std::make_unique<NearestNeighbour>(context);
  };
  return c;
}

ValidationConfig rgb2spec_fit_row() {
  ValidationConfig c;
  c.name = "rgb2spec, fitted per colour (Jakob & Hanika 2019; reference, not exact)";
  c.exact = false;
  c.make = [](const RowContext& context) -> std::unique_ptr<Reconstruction> {
    return std::make_unique<Rgb2specFit>(context);
  };
  return c;
}

ValidationConfig rgb2spec_table_row() {
  ValidationConfig c;
  c.name = "rgb2spec, 64³ table as pbrt-v4 renders it (reference, not exact)";
  c.exact = false;
  c.make = [](const RowContext& context) -> std::unique_ptr<Reconstruction> {
    return std::make_unique<Rgb2specTable>(context);
  };
  return c;
}

std::vector<ValidationConfig> reference_rows() {
  return {rgb2spec_fit_row(), rgb2spec_table_row(), nearest_neighbour_row()};
}

}  // namespace spectralize::figures
