// One loaded table serves every thread: it is read-only after spz_table_load, and fetch and
// eval only read it. Each thread keeps its own spz_spectrum values (small, on the stack).
// Usage: threads TABLE.spztab
#include <spectralize/rt.h>

#include <atomic>
#include <cstdio>
#include <thread>
#include <vector>

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  char error[512];
  spz_table* table = spz_table_load(argv[1], error, sizeof error);
  if (!table) {
    std::fprintf(stderr, "%s\n", error);
    return 1;
  }
  std::atomic<int> bad{0};
  std::vector<std::thread> workers;
  for (int t = 0; t < 4; ++t)
    workers.emplace_back([&, t] {
      for (int i = 0; i < 10000; ++i) {
        const float rgb[3] = {(i % 97) / 96.0f, (i % 89) / 88.0f, ((i + 31 * t) % 83) / 82.0f};
        spz_spectrum s;  // per thread
        if (spz_fetch(table, rgb, &s) != SPZ_EXACT) ++bad;
        const float lambda[4] = {400.0f + t, 500.0f, 600.0f, 700.0f};
        float v[4];
        spz_eval4(&s, lambda, v);
        for (const float x : v)
          if (!(x >= 0.0f && x <= 1.0f)) ++bad;
      }
    });
  for (std::thread& w : workers) w.join();
  spz_table_free(table);  // after every thread is done with it
  std::printf("%s\n", bad == 0 ? "ok" : "FAILED");
  return bad == 0 ? 0 : 1;
}
