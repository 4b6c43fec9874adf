#include "path_tracer/render.h"

#include <OpenImageIO/parallel.h>

#include <algorithm>
#include <array>

#include "spectralize/core/colorimetry.h"
#include "spectralize/core/error.h"

namespace spectralize::path_tracer {

namespace {

// Packets of the dense reference: the 471 table wavelengths in fours.
constexpr std::size_t kMaxPackets = (ReferenceTable::kSize + kLanes - 1) / kLanes;

}  // namespace

Xyz evaluate_path(const PathRecord& path, const SpectralRender& r,
                  std::span<const WavelengthPacket> packets) {
  const std::size_t n = packets.size() * kLanes;
  std::array<float, kMaxPackets * kLanes> throughput, values;
  std::fill(throughput.begin(), throughput.begin() + n, 1.0f);
  double xyz[3] = {0, 0, 0};
  int t = 0;
  for (int d = 0; d <= path.vertices; ++d) {
    // The light terms that have passed d vertices: their radiance times the throughput.
    for (; t < path.term_count && path.terms[t].depth == static_cast<std::uint32_t>(d); ++t) {
      r.light->eval(path.terms[t].texel, packets, values.data());
      for (int c = 0; c < 3; ++c) {
        double sum = 0;
        for (std::size_t p = 0; p < packets.size(); ++p)
          for (int i = 0; i < kLanes; ++i) {
            const std::size_t k = p * kLanes + i;
            sum += packets[p].xyz_weight[c][i] * (values[k] * throughput[k]);
          }
        xyz[c] += path.terms[t].weight * sum;
      }
    }
    if (d == path.vertices || t == path.term_count) break;
    r.surface->eval(path.vertex_texel[d], packets, values.data());
    for (std::size_t k = 0; k < n; ++k) throughput[k] *= values[k];
  }
  return {xyz[0], xyz[1], xyz[2]};
}

RenderResult render(const Scene& scene, const Environment& environment, const SpectralFilm& film,
                    std::span<const SpectralRender> renders, int size, std::vector<int> spp,
                    int threads) {
  if (size < 1 || spp.empty() || spp.front() < 1 ||
      !std::is_sorted(spp.begin(), spp.end(), std::less_equal<int>()) ||
      std::adjacent_find(spp.begin(), spp.end()) != spp.end())
    throw Error("render: need a size >= 1 and increasing sample counts >= 1");
  for (const SpectralRender& r : renders)
    if (!r.surface || !r.light) throw Error("render '" + r.name + "': no textures");
  RenderResult result;
  result.size = size;
  result.spp = spp;
  const std::size_t pixels = static_cast<std::size_t>(size) * size;
  result.images.assign(renders.size(),
                       std::vector<std::vector<Xyz>>(spp.size(), std::vector<Xyz>(pixels)));
  result.coverage.assign(pixels, 0.0f);
  const int max_spp = spp.back();
  OIIO::parallel_for(
      int64_t{0}, static_cast<int64_t>(size),
      [&](int64_t y) {
        std::vector<Xyz> sum(renders.size());
        for (int x = 0; x < size; ++x) {
          const std::size_t pixel = static_cast<std::size_t>(y) * size + x;
          std::fill(sum.begin(), sum.end(), Xyz{});
          std::size_t next = 0;
          int hits = 0;
          for (int s = 0; s < max_spp; ++s) {
            const PathRecord path = trace_path(scene, environment, x, static_cast<int>(y), size,
                                               static_cast<std::uint64_t>(s));
            hits += path.vertices > 0;
            const WavelengthPacket hero = film.hero(wavelength_offset(pixel, s));
            for (std::size_t r = 0; r < renders.size(); ++r) {
              const std::span<const WavelengthPacket> packets =
                  renders[r].dense ? std::span<const WavelengthPacket>(film.reference())
                                   : std::span<const WavelengthPacket>(&hero, 1);
              sum[r] = sum[r] + evaluate_path(path, renders[r], packets);
            }
            if (s + 1 == spp[next]) {
              for (std::size_t r = 0; r < renders.size(); ++r)
                result.images[r][next][pixel] = (1.0 / (s + 1)) * sum[r];
              ++next;
            }
          }
          result.coverage[pixel] = static_cast<float>(hits) / static_cast<float>(max_spp);
        }
      },
      OIIO::paropt(threads));
  return result;
}

}  // namespace spectralize::path_tracer
