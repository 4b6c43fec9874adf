// The C++ side of the Python speed comparison (tests/bench/bench_python.py): the same colours
// (raw float32 R,G,B triples from a file) through ColourArrays, the path spectralize.spectra()
// takes, and through the bare SpectralTable (XYZ in, no OCIO), warm, timed over `runs` calls.
// Prints one line per path: "<name> <colours> <median seconds>".
// Usage: bench_colour_arrays COLOURS.f32 RUNS

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <vector>

#include "io/colour_array.h"

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
  if (argc != 3) {
    std::fprintf(stderr, "usage: bench_colour_arrays COLOURS.f32 RUNS\n");
    return 2;
  }
  std::ifstream in(argv[1], std::ios::binary | std::ios::ate);
  std::vector<float> colours(static_cast<std::size_t>(in.tellg()) / sizeof(float));
  in.seekg(0);
  in.read(reinterpret_cast<char*>(colours.data()),
          static_cast<std::streamsize>(colours.size() * sizeof(float)));
  const std::size_t n = colours.size() / 3;
  const int runs = std::atoi(argv[2]);

  TablePool pool;
  ColourArrays arrays(Settings{}, pool, [](int, const std::string&) {});
  std::vector<float> out(n * arrays.bands());
  arrays.spectra(colours.data(), n, out.data());  // warm: every node the colours need
  std::printf("cpp_colour_arrays %zu %.6f\n", n,
              median_seconds(runs, [&] { arrays.spectra(colours.data(), n, out.data()); }));

  // The bare table on the same colours as XYZ (what the image kernel's table step costs).
  Settings s;
  s.spectral.mode = Mode::emission;
  TablePool::Entry& e = pool.get(s, [](int, const std::string&) {});
  std::vector<Xyz> xyz(n);
  for (std::size_t i = 0; i < n; ++i)
    xyz[i] = {colours[i * 3], colours[i * 3 + 1], colours[i * 3 + 2]};
  std::vector<PixelResult> results(n);
  e.table->spectra(xyz.data(), n, out.data(), results.data());
  std::printf("cpp_table_single_thread %zu %.6f\n", n, median_seconds(runs, [&] {
                e.table->spectra(xyz.data(), n, out.data(), results.data());
              }));
  return 0;
}
