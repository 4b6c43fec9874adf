#include "figures/reference_rows.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/bounded_projection.h"
#include "figures/colour_difference.h"

namespace spectralize::figures {

namespace {

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

std::vector<ValidationConfig> reference_rows() {
  return {nearest_neighbour_row()};
}

}  // namespace spectralize::figures
