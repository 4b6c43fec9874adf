// Google Benchmark kernels of the exact spectralizer (make bench).
// BM_NaiveInverses is the naive baseline: a scalar loop over all C(N,3) triples with
// precomputed 3x3 inverses. BM_SumAdmissible is the same work (enumerate, solve, sum the
// admissible partial solutions) done by PaperSolver.

#include <benchmark/benchmark.h>

// The benchmark's one unit: it compiles the evaluator's definitions
// (include/spectralize/rt_impl.hpp).
#define SPECTRALIZE_RT_IMPLEMENTATION
#include <spectralize/rt.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstring>
#include <functional>
#include <thread>
#include <vector>

#include "baseline/sigmoid_spectrum.h"
#include "bench_colours.h"
#include "core/models/exemplar_model.h"
#include "core/solvers/paper_solver.h"
#include "core/tables/exact_table.h"
#include "core/tables/spectral_table.h"
#include "core/tables/table_file.h"
#include "rgb2spec_c.h"
#include "spectralize/core/spectralizer.h"

using namespace spectralize;
using bench::rec709;
using bench::srgb_decode;

namespace {

// Linear Rec.709 -> XYZ (D65), the paper's light and a few colours to cycle through.

const std::vector<Xyz>& colours() {
  static const std::vector<Xyz> c = {rec709(6000, 5000, 1000), rec709(0.21, 0.72, 0.15),
                                     rec709(0.8, 0.3, 0.2),    rec709(0.2, 0.4, 0.9),
                                     rec709(0.5, 0.5, 0.5),    rec709(0.9, 0.8, 0.1)};
  return c;
}

// The naive baseline: every triple, its stored inverse matrix, a scalar loop.
struct NaiveInverses {
  std::vector<std::array<int, 3>> triples;
  std::vector<std::array<double, 9>> inverses;
  explicit NaiveInverses(const std::vector<Xyz>& w) {
    const int n = static_cast<int>(w.size());
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j)
        for (int k = j + 1; k < n; ++k) {
          const Xyz a = w[i], b = w[j], c = w[k];
          double det = dot(a, cross(b, c));
          if (det == 0) continue;
          // Rows of the inverse of [a b c] (columns) are the cross products / det.
          Xyz r0 = cross(b, c), r1 = cross(c, a), r2 = cross(a, b);
          triples.push_back({i, j, k});
          inverses.push_back({r0.X / det, r0.Y / det, r0.Z / det, r1.X / det, r1.Y / det,
                              r1.Z / det, r2.X / det, r2.Y / det, r2.Z / det});
        }
  }
  std::size_t sum(const Xyz& t, std::vector<double>& out) const {
    std::fill(out.begin(), out.end(), 0.0);
    std::size_t count = 0;
    for (std::size_t m = 0; m < triples.size(); ++m) {
      const auto& inv = inverses[m];
      double p0 = inv[0] * t.X + inv[1] * t.Y + inv[2] * t.Z;
      double p1 = inv[3] * t.X + inv[4] * t.Y + inv[5] * t.Z;
      double p2 = inv[6] * t.X + inv[7] * t.Y + inv[8] * t.Z;
      if (p0 >= 0 && p1 >= 0 && p2 >= 0) {
        out[triples[m][0]] += p0;
        out[triples[m][1]] += p1;
        out[triples[m][2]] += p2;
        ++count;
      }
    }
    return count;
  }
};

WavelengthGrid grid_for(int step) {
  return WavelengthGrid(380, 780, step);
}

void BM_NaiveInverses(benchmark::State& state) {
  SpectralizerSettings s;
  s.grid = grid_for(static_cast<int>(state.range(0)));
  Spectralizer sp(s);
  NaiveInverses naive(sp.weights().columns());
  std::vector<double> out(s.grid.size());
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(naive.sum(colours()[i++ % colours().size()], out));
    benchmark::ClobberMemory();
  }
}

void BM_SumAdmissible(benchmark::State& state) {
  SpectralizerSettings s;
  s.grid = grid_for(static_cast<int>(state.range(0)));
  Spectralizer sp(s);
  PaperSolver solver(sp.weights().columns());
  std::vector<double> out(s.grid.size());
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(solver.sum_admissible(colours()[i++ % colours().size()], out));
    benchmark::ClobberMemory();
  }
}

// Full solve of one colour, gamut test included. Paper model: edge filter, exact polish and
// (reflectance) the rho <= 1 bound. Smooth model: the least-roughness quadratic programme.
// Natural model: Newton on the link's Lagrangian, the depth, the fallback where it applies.
// Exemplar model: natural plus the distances to the 214 measured colours (and a projection
// for the colours near one).
void BM_FullSolve(benchmark::State& state) {
  SpectralizerSettings s;
  s.grid = grid_for(static_cast<int>(state.range(0)));
  s.mode = state.range(1) ? Mode::reflectance : Mode::emission;
  const char* models[] = {"paper", "smooth", "natural", "exemplar"};
  s.model = models[state.range(2)];
  Spectralizer sp(s);
  std::size_t i = 1;  // skip the 6000-lm light in reflectance runs' cycle start
  for (auto _ : state) {
    Xyz c = colours()[i++ % colours().size()];
    if (s.mode == Mode::reflectance && c.Y > 1) c = (0.5 / c.Y) * c;
    benchmark::DoNotOptimize(sp.spectralize(c));
  }
}

// The exemplar model's worst usual case: reflectances at the measured colours themselves (each
// of the 214 development patches, as its target), where every solve blends and projects.
void BM_ExemplarNearMeasured(benchmark::State& state) {
  SpectralizerSettings s;
  s.mode = Mode::reflectance;
  s.model = "exemplar";
  Spectralizer sp(s);
  std::vector<double> nm;
  for (std::size_t k = 0; k < s.grid.size(); ++k) nm.push_back(s.grid[k]);
  std::vector<Xyz> targets;
  for (const std::vector<double>& rho : development_reflectances(nm))
    targets.push_back(sp.weights().integrate(rho));
  std::size_t i = 0;
  for (auto _ : state)
    benchmark::DoNotOptimize(sp.spectralize_target(targets[i++ % targets.size()]));
}

// Spectral synthesis alone with a warm table: one pixel's spectrum from its colour (target,
// cell lookup, 4 or 8 node blend) at 81 bands, one thread; nodes are computed before timing.
// Arg "image" 1: a 256x256 smooth colour field with 2% noise, like an image (neighbours share
// cells); 0: 64k independent random linear sRGB colours (every pixel a cache miss, worst case).
// The pixels of the table benchmarks, linear Rec.709 RGB in [0, 1]: a 256x256 smooth colour
// field with 2% noise (image) or 64k independent random colours.
// kind 1: image-like (a smooth walk through the cube with a little noise); 0: independent
// random colours; 2: random colours with a channel above 0.95 (cells at the reflectance
// solid's boundary in sRGB).
std::vector<std::array<float, 3>> benchmark_pixels(int kind) {
  const bool image = kind == 1;
  std::vector<std::array<float, 3>> pixels(1 << 16);
  std::uint32_t seed = 12345;
  auto rnd = [&] { return (seed = seed * 1664525u + 1013904223u) / 4294967296.0; };
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    if (image) {
      const double u = (i % 256) / 255.0, v = (i / 256) / 255.0;
      pixels[i] = {float(0.1 + 0.8 * u + 0.02 * rnd()), float(0.2 + 0.6 * v + 0.02 * rnd()),
                   float(0.5 - 0.3 * u * v + 0.02 * rnd())};
    } else {
      do {
        pixels[i] = {float(rnd()), float(rnd()), float(rnd())};
      } while (kind == 2 && std::max({pixels[i][0], pixels[i][1], pixels[i][2]}) <= 0.95f);
    }
  }
  return pixels;
}

void BM_TableSynthesis(benchmark::State& state) {
  SpectralizerSettings s;
  s.mode = state.range(0) ? Mode::reflectance : Mode::emission;
  Spectralizer sp(s);
  SpectralTable table(sp);
  std::vector<Xyz> pixels;
  for (const auto& p : benchmark_pixels(state.range(1))) pixels.push_back(rec709(p[0], p[1], p[2]));
  std::vector<float> out(pixels.size() * s.grid.size());
  std::vector<PixelResult> results(pixels.size());
  table.spectra(pixels.data(), pixels.size(), out.data(), results.data());  // warm the nodes
  for (auto _ : state) {
    table.spectra(pixels.data(), pixels.size(), out.data(), results.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(pixels.size()));
}

// Four wavelengths per colour, as a path's hero wavelengths: one uniform draw in 360-830 nm and
// three rotations of it (the same sequence for every benchmark).
std::vector<float> hero_wavelengths(std::size_t colours) {
  std::vector<float> nm(colours * 4);
  std::uint32_t seed = 777;
  for (std::size_t i = 0; i < colours; ++i) {
    const float u = (seed = seed * 1664525u + 1013904223u) / 4294967296.0f;
    for (int j = 0; j < 4; ++j) nm[4 * i + j] = 360.0f + 470.0f * std::fmod(u + 0.25f * j, 1.0f);
  }
  return nm;
}

// The baseline renderers use (Jakob & Hanika 2019, pbrt-v4's RGBToSpectrumTable; a 64^3 sRGB
// table, built before timing): per pixel the trilinear fetch of the 3 coefficients, then the
// sigmoid at 4 wavelengths (bands 4: a renderer's hero-wavelength sample, 4 stratified
// wavelengths from a random offset per pixel) or at the 81 bands of 380:780:5 (bands 81: the
// output of BM_TableSynthesis), one thread, the same pixels as BM_TableSynthesis (reflectance).
void BM_SigmoidTableFetch(benchmark::State& state) {
  static const baseline::SigmoidFitter fitter(bench::kRec709ToXyz);
  static const baseline::SigmoidTable table(fitter, 64, 2);
  const auto pixels = benchmark_pixels(state.range(0));
  const int bands = static_cast<int>(state.range(1));
  const std::vector<float> nm = hero_wavelengths(pixels.size());
  float grid[81];
  for (int b = 0; b < 81; ++b) grid[b] = 380.0f + 5.0f * b;
  std::vector<float> out(pixels.size() * bands);
  for (auto _ : state) {
    if (bands == 4) {
      for (std::size_t i = 0; i < pixels.size(); ++i) {
        const auto& p = pixels[i];
        table(p[0], p[1], p[2]).eval4(&nm[4 * i], &out[4 * i]);
      }
    } else {
      for (std::size_t i = 0; i < pixels.size(); ++i) {
        const auto& p = pixels[i];
        const baseline::SigmoidPolynomial c = table(p[0], p[1], p[2]);
        float* o = &out[81 * i];
        for (int b = 0; b < 80; b += 4) c.eval4(grid + b, o + b);
        o[80] = c(grid[80]);
      }
    }
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(pixels.size()));
}

// The same table as renderers run it: the original rgb2spec's fetch and 4 x eval_precise in
// plain C at -O3 (rgb2spec_c.c), from the same 64^3 coefficients and the same pixels and
// wavelengths: the baseline's speed as published, not as this C++ port's.
void BM_Rgb2specC(benchmark::State& state) {
  static const baseline::SigmoidFitter fitter(bench::kRec709ToXyz);
  static const baseline::SigmoidTable table(fitter, 64, 2);
  static const std::vector<float> scale = [] {
    std::vector<float> s(64);
    for (int k = 0; k < 64; ++k) s[k] = table.z_node(k);
    return s;
  }();
  static const std::vector<float> data = [] {
    std::vector<float> d;
    for (int m = 0; m < 3; ++m)
      for (int k = 0; k < 64; ++k)
        for (int j = 0; j < 64; ++j)
          for (int i = 0; i < 64; ++i) {
            const baseline::SigmoidPolynomial c = table.node(m, k, j, i);
            d.insert(d.end(), {c.c0, c.c1, c.c2});
          }
    return d;
  }();
  const rgb2spec_c model{64, scale.data(), data.data()};
  const auto pixels = benchmark_pixels(state.range(0));
  const std::vector<float> nm = hero_wavelengths(pixels.size());
  std::vector<float> out(pixels.size() * 4);
  for (auto _ : state) {
    for (std::size_t i = 0; i < pixels.size(); ++i) {
      float c[3];
      rgb2spec_c_fetch(&model, pixels[i].data(), c);
      for (int j = 0; j < 4; ++j) out[4 * i + j] = rgb2spec_c_eval_precise(c, nm[4 * i + j]);
    }
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(pixels.size()));
}

// The render-time table (include/spectralize/rt.hpp) of linear sRGB reflectances, as
// `spectralize table` makes it (built before timing, read from memory by the evaluator).
const spz::TableView& srgb_table() {
  static const std::string bytes = [] {
    SpectralizerSettings s;
    s.mode = Mode::reflectance;
    static const Spectralizer sp(s);
    Mat3 frame;
    for (int i = 0; i < 9; ++i) frame[i] = bench::kRec709ToXyz[i / 3][i % 3];
    ExactTable table(sp, frame);
    table.build([](std::size_t n, const std::function<void(std::size_t, std::size_t)>& body) {
      std::atomic<std::size_t> next{0};
      std::vector<std::thread> pool;
      for (int t = 0; t < 2; ++t)
        pool.emplace_back([&] {
          for (std::size_t b; (b = next.fetch_add(64)) < n;) body(b, std::min(n, b + 64));
        });
      for (auto& t : pool) t.join();
    });
    return encode_table_file(table, sp, {"Linear Rec.709 (sRGB)", "lin_rec709_scene"});
  }();
  static const std::vector<std::uint64_t> aligned = [] {
    std::vector<std::uint64_t> a(bytes.size() / 8 + 1);
    std::memcpy(a.data(), bytes.data(), bytes.size());
    return a;
  }();
  static spz::TableView view;
  static const bool ok = view.open(aligned.data(), bytes.size(), nullptr, 0);
  if (!ok) std::abort();
  return view;
}

// spz_fetch + spz_eval4 (bands 4: the same hero wavelengths per pixel as BM_SigmoidTableFetch)
// or + the 81 samples (bands 81), one thread, the same pixels: against BM_SigmoidTableFetch.
void BM_SpzFetch(benchmark::State& state) {
  const spz::TableView& table = srgb_table();
  const auto pixels = benchmark_pixels(state.range(0));
  const int bands = static_cast<int>(state.range(1));
  const std::vector<float> nm = hero_wavelengths(pixels.size());
  std::vector<float> out(pixels.size() * bands);
  for (auto _ : state) {
    if (bands == 4) {  // the bands chosen outside the loop, as BM_SigmoidTableFetch does
      for (std::size_t i = 0; i < pixels.size(); ++i) {
        spz::Spectrum s;
        table.fetch(pixels[i].data(), s);
        spz::eval4(s, &nm[4 * i], &out[4 * i]);
      }
    } else {
      for (std::size_t i = 0; i < pixels.size(); ++i) {
        spz::Spectrum s;
        table.fetch(pixels[i].data(), s);
        spz::samples(s, &out[81 * i]);
      }
    }
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(pixels.size()));
}

// The same lookups through fetch_eval4 (one call, as a texture lookup that evaluates at once).
void BM_SpzFetchEval4(benchmark::State& state) {
  const spz::TableView& table = srgb_table();
  const auto pixels = benchmark_pixels(state.range(0));
  const std::vector<float> nm = hero_wavelengths(pixels.size());
  std::vector<float> out(pixels.size() * 4);
  for (auto _ : state) {
    for (std::size_t i = 0; i < pixels.size(); ++i)
      table.fetch_eval4(pixels[i].data(), &nm[4 * i], &out[4 * i]);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(pixels.size()));
}

// Whole 81-band spectra into an array, by threads: each thread fills its own array with the
// spectra of the 65,536 image-like colours (as a renderer's workers would); items are summed
// over the threads, per second of wall time.
void BM_SpzSpectraArray(benchmark::State& state) {
  const spz::TableView& table = srgb_table();
  static const auto pixels = benchmark_pixels(1);
  std::vector<float> out(pixels.size() * 81);
  for (auto _ : state) {
    for (std::size_t i = 0; i < pixels.size(); ++i) {
      spz::Spectrum s;
      table.fetch(pixels[i].data(), s);
      spz::samples(s, &out[81 * i]);
    }
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(pixels.size()));
}

}  // namespace

BENCHMARK(BM_SpzFetch)
    ->ArgNames({"image", "bands"})
    ->Args({1, 4})
    ->Args({0, 4})
    ->Args({1, 81})
    ->Args({0, 81})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SpzFetchEval4)->ArgNames({"image"})->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Rgb2specC)->ArgNames({"image"})->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SpzSpectraArray)->Threads(1)->Threads(2)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SigmoidTableFetch)
    ->ArgNames({"image", "bands"})
    ->Args({1, 4})
    ->Args({0, 4})
    ->Args({1, 81})
    ->Args({0, 81})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TableSynthesis)
    ->ArgNames({"reflectance", "image"})
    ->Args({0, 1})
    ->Args({1, 1})
    ->Args({0, 0})
    ->Args({1, 0})
    ->Args({0, 2})
    ->Args({1, 2})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TableSynthesis)
    ->Name("BM_TableSynthesis/threads")
    ->Args({1, 1})
    ->Threads(2)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_NaiveInverses)->Arg(10)->Arg(5)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SumAdmissible)->Arg(10)->Arg(5)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FullSolve)
    ->ArgNames({"step", "reflectance", "model"})  // 0 paper, 1 smooth, 2 natural, 3 exemplar
    ->Args({10, 0, 0})
    ->Args({5, 0, 0})
    ->Args({5, 1, 0})
    ->Args({1, 0, 0})
    ->Args({10, 0, 1})
    ->Args({5, 0, 1})
    ->Args({5, 1, 1})
    ->Args({1, 0, 1})
    ->Args({10, 0, 2})
    ->Args({5, 0, 2})
    ->Args({5, 1, 2})
    ->Args({1, 0, 2})
    ->Args({5, 0, 3})
    ->Args({5, 1, 3})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ExemplarNearMeasured)->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
