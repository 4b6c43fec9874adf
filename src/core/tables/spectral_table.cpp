#include "core/tables/spectral_table.h"

#include <spectralize/rt.hpp>

#include <algorithm>
#include <cmath>

#include "core/multiversion.h"
#include "spectralize/core/error.h"

namespace spectralize {

// FNV-1a, 64 bit (the table checksum's, spectralize/rt.hpp): spreads the direct-solve cache's
// keys over its shards.
std::size_t SpectralTable::TargetHash::operator()(const TargetKey& k) const {
  return static_cast<std::size_t>(
      spz::detail::fnv1a(reinterpret_cast<const unsigned char*>(&k), sizeof k));
}

SpectralTable::SpectralTable(const Spectralizer& spectralizer, Method method, const Mat3& frame)
    : sp_(spectralizer),
      method_(method),
      bands_(spectralizer.settings().grid.size()),
      exact_(spectralizer, frame) {
  if (spectralizer.settings().mode == Mode::emission) {
    basis_.assign(spectralizer.basis().begin(), spectralizer.basis().end());
    basis_white_ = spectralizer.weights().integrate(spectralizer.basis());
  }
}

PixelResult SpectralTable::direct(const Xyz& target, float* out) {
  const TargetKey key{target.X, target.Y, target.Z};
  Shard& shard = shards_[TargetHash{}(key) % shards_.size()];
  {
    std::lock_guard<std::mutex> lock(shard.mutex);
    auto it = shard.solved.find(key);
    if (it != shard.solved.end()) {
      std::copy(it->second.values.begin(), it->second.values.end(), out);
      fallback_hits_++;
      return it->second.result;
    }
  }
  // Solve outside the lock; two threads may solve the same colour once each, same result.
  SpectrumResult r = sp_.spectralize_target(target);
  Solved solved;
  solved.values.assign(r.values.begin(), r.values.end());
  solved.result.kind = r.status;
  solved.result.fallback = true;
  solved.result.target = r.target;
  std::copy(solved.values.begin(), solved.values.end(), out);
  fallback_solves_++;
  PixelResult result = solved.result;
  std::lock_guard<std::mutex> lock(shard.mutex);
  shard.solved.emplace(key, std::move(solved));
  return result;
}

inline void SpectralTable::pixel(const Xyz& xyz_d65, float* out, PixelResult& res) {
  res.kind = Outcome::exact;
  res.fallback = false;
  if (!xyz_d65.finite()) {
    std::fill(out, out + bands_, 0.0f);
    res.kind = Outcome::invalid;
    return;
  }
  const Xyz t = sp_.target_of(xyz_d65);
  if (t == Xyz{}) {
    std::fill(out, out + bands_, 0.0f);
    res.kind = Outcome::black;
    return;
  }
  if (t.Y < 0) {
    std::fill(out, out + bands_, 0.0f);
    res.kind = Outcome::negative;
    return;
  }
  if (method_ == Method::exact) return void(res = direct(t, out));
  if (!basis_.empty()) {
    const double k = t.Y / basis_white_.Y;
    if (relative_error(t, k * basis_white_) <= kSnapTolerance) {
      for (std::size_t i = 0; i < bands_; ++i) out[i] = static_cast<float>(k * basis_[i]);
      res.target = k * basis_white_;
      return;
    }
  }
  TableBlend blend;
  if (exact_.locate(t, blend)) {
    exact_.blend_into(blend, out);
    res.target = t;
    return;
  }
  // Outside the gamut (or within its rounding): mapped as every model maps (docs/DESIGN.md
  // §5), then the blend of the mapped colour's cell.
  Outcome mapping = Outcome::exact;
  const Xyz mapped = sp_.mapped_target(t, mapping);
  res.kind = mapping;
  res.target = mapped;
  if (!(mapped.Y > 0)) {  // a colour of zero luminance maps to black
    std::fill(out, out + bands_, 0.0f);
    res.target = Xyz{};
    return;
  }
  if (exact_.locate(mapped, blend, /*nearest=*/true)) return exact_.blend_into(blend, out);
  // Not reached for a gamut-mapped colour (it is inside by a margin); solved exactly if so.
  const Outcome kind = res.kind;
  res = direct(mapped, out);
  if (kind != Outcome::exact) res.kind = kind;
}

// The blend loops vectorise well: compiled for AVX2 (with FMA) and baseline x86-64, picked at
// load time.
SPECTRALIZE_MULTIVERSION_V3 void SpectralTable::spectra(const Xyz* xyz_d65, std::size_t n,
                                                        float* out, PixelResult* results,
                                                        std::size_t stride) {
  if (stride == 0) stride = bands_;
  for (std::size_t i = 0; i < n; ++i) pixel(xyz_d65[i], out + i * stride, results[i]);
}

TableStats SpectralTable::stats() const {
  const ExactTableStats e = exact_.stats();
  TableStats s;
  s.nodes_computed = e.nodes_computed;
  s.nodes_loaded = e.nodes_loaded;
  s.nodes_infeasible = e.nodes_outside;
  s.nodes_constructed = e.nodes_constructed;
  s.boundary_cells = e.boundary_cells;
  s.fallback_solves = fallback_solves_.load();
  s.fallback_hits = fallback_hits_.load();
  return s;
}

}  // namespace spectralize
