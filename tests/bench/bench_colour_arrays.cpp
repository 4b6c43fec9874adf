// The C++ side of the Python speed comparison (tests/bench/bench_python.py): the same colours
// (raw float32 R,G,B triples from a file) through ColourArrays, the path spectralize.spectra()
// takes, and through the bare SpectralTable (XYZ in, no OCIO), warm, timed over `runs` calls.
// Prints one line per path: "<name> <colours> <median seconds>".
// Usage: bench_colour_arrays COLOURS.f32 RUNS [emission|reflectance]

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "core/tables/spectral_table.h"
#include "pipeline/colour_array.h"
#include "pipeline/table_pool.h"

using namespace spectralize;

namespace {

template <class Fn>
double median_seconds(int runs, Fn&& fn) {
  std::vector<double> t;
  for (int i = 0; i < runs; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    fn();
    t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3 && argc != 4) {
    std::fprintf(stderr, "usage: bench_colour_arrays COLOURS.f32 RUNS [emission|reflectance]\n");
    return 2;
  }
  std::ifstream in(argv[1], std::ios::binary | std::ios::ate);
  std::vector<float> colours(static_cast<std::size_t>(in.tellg()) / sizeof(float));
  in.seekg(0);
  in.read(reinterpret_cast<char*>(colours.data()),
          static_cast<std::streamsize>(colours.size() * sizeof(float)));
  const std::size_t n = colours.size() / 3;
  const int runs = std::atoi(argv[2]);

  const Mode mode =
      argc > 3 && std::string(argv[3]) == "reflectance" ? Mode::reflectance : Mode::emission;
  Settings settings;
  settings.spectral.mode = mode;
  TablePool pool;
  ColourArrays arrays(settings, pool, [](int, const std::string&) {});
  std::vector<float> out(n * arrays.bands());
  arrays.spectra(colours.data(), n, out.data());  // warm: every node the colours need
  std::printf("cpp_colour_arrays %zu %.6f\n", n,
              median_seconds(runs, [&] { arrays.spectra(colours.data(), n, out.data()); }));

  // The bare table on the same colours as XYZ (what the image kernel's table step costs).
  Settings s;
  s.spectral.mode = mode;
  TablePool::Entry& e = pool.get(s, kRec709Frame, [](int, const std::string&) {});
  std::vector<Xyz> xyz(n);  // Linear Rec.709 -> XYZ (the frame's matrix)
  for (std::size_t i = 0; i < n; ++i) {
    const float* c = &colours[i * 3];
    xyz[i] = {kRec709Frame[0] * c[0] + kRec709Frame[1] * c[1] + kRec709Frame[2] * c[2],
              kRec709Frame[3] * c[0] + kRec709Frame[4] * c[1] + kRec709Frame[5] * c[2],
              kRec709Frame[6] * c[0] + kRec709Frame[7] * c[1] + kRec709Frame[8] * c[2]};
  }
  std::vector<PixelResult> results(n);
  e.table->spectra(xyz.data(), n, out.data(), results.data());
  std::printf("cpp_table_single_thread %zu %.6f\n", n, median_seconds(runs, [&] {
                e.table->spectra(xyz.data(), n, out.data(), results.data());
              }));
  return 0;
}
