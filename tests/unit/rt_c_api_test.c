/* The C API of spectralize::rt from a C translation unit (C99): loads a table, fetches a
 * colour and checks what a renderer relies on: the status, the bounds, eval against the
 * samples, eval4 against eval, zero outside the wavelengths, and the error message of a bad
 * path. The implementation is in rt_c_api_impl.cpp (SPECTRALIZE_RT_IMPLEMENTATION).
 * Usage: rt_c_api_test TABLE.spztab (reflectance); prints "ok" and exits 0. */
#include <spectralize/rt.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

static int failures = 0;
#define CHECK(cond)                                             \
  do {                                                          \
    if (!(cond)) {                                              \
      fprintf(stderr, "FAILED line %d: %s\n", __LINE__, #cond); \
      ++failures;                                               \
    }                                                           \
  } while (0)

int main(int argc, char** argv) {
  char error[256];
  spz_table* table;
  spz_spectrum s;
  const float rgb[3] = {0.2f, 0.5f, 0.1f};
  const float lambda[4] = {400.0f, 512.5f, 655.0f, 900.0f};
  float values[4], samples[1024], start, step;
  size_t bands, k;
  if (argc != 2) return 2;
  CHECK(spz_table_load("/nonexistent/table.spztab", error, sizeof error) == NULL);
  CHECK(strstr(error, "/nonexistent/table.spztab") != NULL);
  table = spz_table_load(argv[1], error, sizeof error);
  if (!table) {
    fprintf(stderr, "FAILED: %s\n", error);
    return 1;
  }
  CHECK(spz_table_mode(table) == 1);
  CHECK(strlen(spz_table_colorspace(table)) > 0);
  bands = spz_table_bands(table);
  CHECK(bands >= 2 && bands <= 1024);
  spz_table_wavelengths(table, &start, &step);
  CHECK(spz_fetch(table, rgb, &s) == SPZ_EXACT);
  spz_samples(&s, samples);
  for (k = 0; k < bands; ++k) {
    CHECK(samples[k] >= 0.0f && samples[k] <= 1.0f);
    CHECK(fabsf(spz_eval(&s, start + step * (float)k) - samples[k]) <= 1e-6f);
  }
  spz_eval4(&s, lambda, values);
  for (k = 0; k < 4; ++k) CHECK(values[k] == spz_eval(&s, lambda[k]));
  CHECK(values[3] == 0.0f); /* 900 nm: outside the table's wavelengths */
  spz_table_free(table);
  spz_table_free(NULL);
  if (failures) return 1;
  printf("ok\n");
  return 0;
}
