#include "core/spectral_table.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/error.h"

namespace spectralize {

const float SpectralTable::kInfeasibleMark = 0.0f;

namespace {

// FNV-1a, 64 bit: spreads the direct-solve cache's keys over its shards.
std::uint64_t fnv1a(const void* data, std::size_t size) {
  std::uint64_t h = 1469598103934665603ull;
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) h = (h ^ p[i]) * 1099511628211ull;
  return h;
}

constexpr std::size_t kArenaBlockNodes = 1024;
// Node spacing: 1/128 in chromaticity for emission, 1/64 with 16 layers in S = X+Y+Z for
// reflectance (docs/DESIGN.md §4).
constexpr int kEmissionSteps = 128, kReflectanceSteps = 64, kLayers = 16;
// A stored node must reproduce its own colour to float precision (docs/DESIGN.md §4).
constexpr double kStoredNodeTolerance = 1e-5;

PixelKind kind_of(const SpectrumResult& r) {
  switch (r.status) {
    case Status::ok:
      return PixelKind::in_gamut;
    case Status::black:
      return PixelKind::black;
    case Status::invalid:
      return PixelKind::invalid;
    case Status::out_of_gamut:
      return r.outside_locus ? PixelKind::outside_locus : PixelKind::outside_solid;
  }
  return PixelKind::invalid;
}

}  // namespace

std::size_t SpectralTable::TargetHash::operator()(const TargetKey& k) const {
  return static_cast<std::size_t>(fnv1a(&k, sizeof k));
}

SpectralTable::SpectralTable(const Spectralizer& spectralizer, Method method)
    : sp_(spectralizer), method_(method), bands_(spectralizer.settings().grid.size()) {
  const bool reflectance = sp_.settings().mode == Mode::reflectance;
  xy_steps_ = reflectance ? kReflectanceSteps : kEmissionSteps;
  s_steps_ = kLayers;
  nx_ = static_cast<int>(std::ceil(kXMax * xy_steps_)) + 1;
  ny_ = static_cast<int>(std::ceil(kYMax * xy_steps_)) + 1;
  ns_ = reflectance ? s_steps_ + 1 : 1;
  // The brightest reflectance is the reference white; nothing in the solid has a larger S.
  s_max_ = reflectance ? sp_.weights().unit_white().sum() : 1.0;
  node_count_ = static_cast<std::size_t>(nx_) * ny_ * ns_;
  nodes_ = std::make_unique<std::atomic<const float*>[]>(node_count_);
  for (std::size_t i = 0; i < node_count_; ++i) nodes_[i].store(nullptr, std::memory_order_relaxed);
}

std::string SpectralTable::layout() const {
  return "nodes " + std::to_string(nx_) + "x" + std::to_string(ny_) + "x" + std::to_string(ns_) +
         " step 1/" + std::to_string(xy_steps_) + " S/" + std::to_string(s_steps_);
}

Xyz SpectralTable::node_target(std::size_t index) const {
  const std::size_t per_layer = static_cast<std::size_t>(nx_) * ny_;
  const int is = static_cast<int>(index / per_layer);
  const std::size_t rest = index % per_layer;
  const double x = static_cast<double>(rest % nx_) / xy_steps_;
  const double y = static_cast<double>(rest / nx_) / xy_steps_;
  const double S = ns_ > 1 ? s_max_ * is / s_steps_ : 1.0;
  return {S * x, S * y, S * (1 - x - y)};
}

float* SpectralTable::allocate_node() {
  std::lock_guard<std::mutex> lock(arena_mutex_);
  if (arena_.empty() || arena_used_ == kArenaBlockNodes) {
    arena_.emplace_back(kArenaBlockNodes * bands_);
    arena_used_ = 0;
  }
  return arena_.back().data() + bands_ * arena_used_++;
}

const float* SpectralTable::compute_node(std::size_t index) {
  std::lock_guard<std::mutex> lock(node_locks_[index % node_locks_.size()]);
  const float* ready = nodes_[index].load(std::memory_order_acquire);
  if (ready) return ready;  // another thread was first
  const Xyz t = node_target(index);
  const float* result = &kInfeasibleMark;
  if (t == Xyz{}) {
    float* zeros = allocate_node();
    std::fill(zeros, zeros + bands_, 0.0f);
    result = zeros;
  } else if (t.Y > 0 && t.Z >= 0 && sp_.in_gamut(t)) {
    SpectrumResult r = sp_.spectralize_target(t);
    // A node is only usable if its spectrum reproduces the node's colour itself.
    if (r.status == Status::ok && r.relative_error <= 1e-9 &&
        relative_error(r.target, t) <= 1e-12) {
      float* values = allocate_node();
      std::copy(r.values.begin(), r.values.end(), values);
      result = values;
    }
  }
  if (result == &kInfeasibleMark) stats_.nodes_infeasible++;
  stats_.nodes_computed++;
  nodes_[index].store(result, std::memory_order_release);
  return result;
}

inline const float* SpectralTable::node(std::size_t index) {
  const float* p = nodes_[index].load(std::memory_order_acquire);
  return p ? p : compute_node(index);
}

PixelResult SpectralTable::direct(const Xyz& target, float* out) {
  const TargetKey key{target.X, target.Y, target.Z};
  Shard& shard = shards_[TargetHash{}(key) % shards_.size()];
  {
    std::lock_guard<std::mutex> lock(shard.mutex);
    auto it = shard.solved.find(key);
    if (it != shard.solved.end()) {
      std::copy(it->second.values.begin(), it->second.values.end(), out);
      stats_.fallback_hits++;
      return it->second.result;
    }
  }
  // Solve outside the lock; two threads may solve the same colour once each, same result.
  SpectrumResult r = sp_.spectralize_target(target);
  Solved solved;
  solved.values.assign(r.values.begin(), r.values.end());
  solved.result.kind = kind_of(r);
  solved.result.fallback = true;
  solved.result.target = r.target;
  std::copy(solved.values.begin(), solved.values.end(), out);
  stats_.fallback_solves++;
  PixelResult result = solved.result;
  std::lock_guard<std::mutex> lock(shard.mutex);
  shard.solved.emplace(key, std::move(solved));
  return result;
}

inline void SpectralTable::pixel(const Xyz& xyz_d65, float* out, PixelResult& res) {
  res.kind = PixelKind::in_gamut;
  res.fallback = false;
  if (!xyz_d65.finite()) {
    std::fill(out, out + bands_, 0.0f);
    res.kind = PixelKind::invalid;
    return;
  }
  const Xyz t = sp_.target_of(xyz_d65);
  if (t == Xyz{}) {
    std::fill(out, out + bands_, 0.0f);
    res.kind = PixelKind::black;
    return;
  }
  if (t.Y < 0) {
    std::fill(out, out + bands_, 0.0f);
    res.kind = PixelKind::negative;
    return;
  }
  const double S = t.sum();
  if (method_ == Method::exact || !(S > 0)) return void(res = direct(t, out));

  // Locate the cell; colours off the node grid are outside the locus: solve directly.
  const double fx = t.X / S * xy_steps_, fy = t.Y / S * xy_steps_;
  const double fs = ns_ > 1 ? S / s_max_ * s_steps_ : 0.0;
  if (!(fx >= 0 && fx < nx_ - 1 && fy >= 0 && fy < ny_ - 1 && fs < ns_ - 1 + (ns_ == 1)))
    return void(res = direct(t, out));
  const int ix = static_cast<int>(fx), iy = static_cast<int>(fy);
  const int is = ns_ > 1 ? static_cast<int>(fs) : 0;
  const float ux = static_cast<float>(fx - ix), uy = static_cast<float>(fy - iy);
  const float us = static_cast<float>(fs - is);

  // The cell's nodes: 4 (emission) or 8 (reflectance), with bi/trilinear weights.
  const std::size_t per_layer = static_cast<std::size_t>(nx_) * ny_;
  const std::size_t base = static_cast<std::size_t>(is) * per_layer +
                           static_cast<std::size_t>(iy) * nx_ + static_cast<std::size_t>(ix);
  const int corners = ns_ > 1 ? 8 : 4;
  const float* p[8];
  float w[8];
  for (int c = 0; c < corners; ++c) {
    const int dx = c & 1, dy = (c >> 1) & 1, ds = (c >> 2) & 1;
    p[c] = node(base + ds * per_layer + dy * nx_ + dx);
    if (p[c] == &kInfeasibleMark)
      return void(res = direct(t, out));  // the cell crosses the gamut boundary
    w[c] = (dx ? ux : 1 - ux) * (dy ? uy : 1 - uy) * (corners == 8 ? (ds ? us : 1 - us) : 1.0f);
  }
  // Emission nodes are spectra of X+Y+Z = 1: scale by the pixel's S.
  const float scale = ns_ > 1 ? 1.0f : static_cast<float>(S);
  for (int c = 0; c < corners; ++c) w[c] *= scale;
  // The output never aliases the node spectra (restrict): the blend vectorises without checks.
  float* __restrict o = out;
  const float w0 = w[0], w1 = w[1], w2 = w[2], w3 = w[3];
  const float* __restrict p0 = p[0], * __restrict p1 = p[1], * __restrict p2 = p[2], * __restrict p3 = p[3];
  const std::size_t n = bands_;
  for (std::size_t i = 0; i < n; ++i) o[i] = w0 * p0[i] + w1 * p1[i] + w2 * p2[i] + w3 * p3[i];
  if (corners == 8) {
    // The upper layer in a second pass: eight streams at once would spill registers.
    const float w4 = w[4], w5 = w[5], w6 = w[6], w7 = w[7];
    const float* __restrict p4 = p[4];
    const float* __restrict p5 = p[5];
    const float* __restrict p6 = p[6];
    const float* __restrict p7 = p[7];
    // Reflectances: a blend of spectra <= 1 is <= 1 in exact arithmetic; float rounding can
    // add an ulp (1 + 2^-23 seen on greys), so the bound is restored bit-exactly.
    for (std::size_t i = 0; i < n; ++i)
      o[i] = std::min(o[i] + w4 * p4[i] + w5 * p5[i] + w6 * p6[i] + w7 * p7[i], 1.0f);
  }
  res.target = t;
}

// The blend loops vectorise well: compiled for AVX2 (with FMA) and baseline x86-64, picked at
// load time.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && \
    !defined(SPECTRALIZE_NO_MULTIVERSION)
__attribute__((target_clones("arch=x86-64-v3", "default")))
#endif
void SpectralTable::spectra(const Xyz* xyz_d65, std::size_t n, float* out,
                            PixelResult* results, std::size_t stride) {
  if (stride == 0) stride = bands_;
  for (std::size_t i = 0; i < n; ++i) pixel(xyz_d65[i], out + i * stride, results[i]);
}

TableStats SpectralTable::stats() const {
  TableStats s;
  s.nodes_computed = stats_.nodes_computed.load();
  s.nodes_loaded = stats_.nodes_loaded.load();
  s.nodes_infeasible = stats_.nodes_infeasible.load();
  s.fallback_solves = stats_.fallback_solves.load();
  s.fallback_hits = stats_.fallback_hits.load();
  return s;
}

void SpectralTable::for_each_node(
    const std::function<void(std::size_t, std::span<const float>)>& fn) const {
  for (std::size_t i = 0; i < node_count_; ++i) {
    const float* p = nodes_[i].load(std::memory_order_acquire);
    if (!p) continue;
    fn(i, p == &kInfeasibleMark ? std::span<const float>() : std::span<const float>(p, bands_));
  }
}

bool SpectralTable::adopt_node(std::size_t index, std::span<const float> values) {
  if (index >= node_count_) return false;
  if (nodes_[index].load(std::memory_order_acquire)) return true;  // already known here
  if (values.empty()) {  // outside the gamut: its cells fall back to exact direct solves
    nodes_[index].store(&kInfeasibleMark, std::memory_order_release);
    stats_.nodes_loaded++;
    return true;
  }
  if (values.size() != bands_) return false;
  // The node must be the spectrum of its own colour, within the bounds: a file with the right
  // key and checksum can still hold wrong spectra (poisoned, or a bug of another version).
  const double upper = sp_.settings().mode == Mode::reflectance ? 1.0 : INFINITY;
  Xyz xyz;
  for (std::size_t i = 0; i < bands_; ++i) {
    if (!(values[i] >= 0 && values[i] <= upper)) return false;
    xyz = xyz + static_cast<double>(values[i]) * sp_.weights().columns()[i];
  }
  if (!(relative_error(xyz, node_target(index)) <= kStoredNodeTolerance)) return false;
  float* stored = allocate_node();
  std::copy(values.begin(), values.end(), stored);
  nodes_[index].store(stored, std::memory_order_release);
  stats_.nodes_loaded++;
  return true;
}

}  // namespace spectralize
