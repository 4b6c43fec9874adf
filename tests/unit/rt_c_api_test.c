/* The C API of spectralize::rt from a C translation unit (C99): loads a table, fetches a
 * colour and checks what a renderer relies on: the status, the bounds, eval against the
 * samples, eval4 against eval, zero outside the wavelengths, the error message of a bad
 * path; the array API against one fetch per colour (rows, statuses, counts), a spectrum's
 * maximum against its samples, fetch_eval4 against fetch and eval4, the zero spectrum and a
 * NULL table. The implementation is in
 * rt_c_api_impl.cpp (SPECTRALIZE_RT_IMPLEMENTATION). Usage: rt_c_api_test TABLE.spztab
 * (reflectance); prints "ok" and exits 0. */
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
  /* The maximum is the largest sample (8 ulp up for eval's rounding), at least every value
   * eval gives between the samples; the zero spectrum's is 0. */
  {
    float most = 0, bound = spz_spectrum_max(&s);
    spz_spectrum zero;
    for (k = 0; k < bands; ++k) most = samples[k] > most ? samples[k] : most;
    CHECK(bound >= most && bound <= most * (1.0f + 1e-6f));
    for (k = 0; k + 1 < bands * 16; ++k) CHECK(spz_eval(&s, start + step * (float)k / 16) <= bound);
    memset(&zero, 0, sizeof zero);
    CHECK(spz_spectrum_max(&zero) == 0.0f && spz_spectrum_bands(&zero) == 0);
    CHECK(spz_spectrum_bands(&s) == bands);
  }
  /* The array API: each row what one fetch and eval give, statuses and counts by kind. */
  {
    const float nan = (float)NAN;
    const float colours[15] = {0.2f, 0.5f,  0.1f,  1.5f,  0.2f, 0.1f, nan, 0.5f,
                               0.5f, -1.0f, -1.0f, -1.0f, 0.3f, 0.3f, 0.3f};
    const int want[5] = {SPZ_EXACT, SPZ_MAPPED, SPZ_INVALID, SPZ_NEGATIVE, SPZ_EXACT};
    static float rows[5 * 1024];
    float at[5 * 4];
    int statuses[5];
    size_t counts[4], i;
    CHECK(spz_fetch_array(table, colours, 5, NULL, 0, rows, statuses, counts) == bands);
    CHECK(counts[0] == 2 && counts[1] == 1 && counts[2] == 1 && counts[3] == 1);
    for (i = 0; i < 5; ++i) {
      spz_spectrum one;
      CHECK(statuses[i] == want[i]);
      CHECK(spz_fetch(table, colours + 3 * i, &one) == want[i]);
      spz_samples(&one, samples);
      for (k = 0; k < bands; ++k) CHECK(rows[i * bands + k] == samples[k]);
    }
    CHECK(spz_fetch_array(table, colours, 5, lambda, 4, at, NULL, NULL) == 4);
    for (i = 0; i < 5; ++i) {
      spz_spectrum one;
      spz_fetch(table, colours + 3 * i, &one);
      for (k = 0; k < 4; ++k) CHECK(at[4 * i + k] == spz_eval(&one, lambda[k]));
    }
    /* No table: zero rows, every colour invalid. */
    CHECK(spz_fetch_array(NULL, colours, 1, lambda, 4, at, statuses, counts) == 4);
    CHECK(statuses[0] == SPZ_INVALID && counts[2] == 1 && at[0] == 0.0f && at[3] == 0.0f);
  }
  /* spz_fetch_eval4 is spz_fetch then spz_eval4, bit for bit: inside cells, in boundary cells,
   * outside the gamut, near black, NaN; the spectrum kept is the one fetched. */
  {
    int r, g, b, mismatches = 0, kinds[4] = {0, 0, 0, 0};
    for (r = 0; r <= 24; ++r)
      for (g = 0; g <= 24; ++g)
        for (b = 0; b <= 25; ++b) {
          float c[3], direct[4], fused[4], fused_alone[4];
          spz_spectrum one, kept;
          int want, got, alone;
          c[0] = -0.2f + 1.5f * (float)r / 24.0f;
          c[1] = -0.2f + 1.5f * (float)g / 24.0f;
          c[2] = b == 25 ? NAN : -0.2f + 1.5f * (float)b / 24.0f;
          if (r == 12 && g == 12) c[0] = c[1] = c[2] = 1e-35f * (float)b; /* near black */
          want = spz_fetch(table, c, &one);
          spz_eval4(&one, lambda, direct);
          got = spz_fetch_eval4(table, c, lambda, fused, &kept);
          alone = spz_fetch_eval4(table, c, lambda, fused_alone, NULL);
          if (got != want || alone != want || memcmp(direct, fused, sizeof direct) != 0 ||
              memcmp(direct, fused_alone, sizeof direct) != 0 ||
              memcmp(&one, &kept, sizeof one) != 0)
            ++mismatches;
          if (want >= SPZ_NEGATIVE && want <= SPZ_MAPPED) ++kinds[want - SPZ_NEGATIVE];
        }
    CHECK(mismatches == 0);
    /* Every kind of result was met: negative, invalid, exact and mapped. */
    CHECK(kinds[0] > 0 && kinds[1] > 0 && kinds[2] > 0 && kinds[3] > 0);
    CHECK(spz_fetch_eval4(NULL, rgb, lambda, values, &s) == SPZ_INVALID);
    CHECK(values[0] == 0.0f && values[3] == 0.0f && spz_eval(&s, 500.0f) == 0.0f);
  }
  /* A NULL table answers without a crash. */
  CHECK(spz_table_bands(NULL) == 0 && spz_table_mode(NULL) == -1);
  CHECK(strcmp(spz_table_colorspace(NULL), "") == 0);
  spz_table_free(table);
  spz_table_free(NULL);
  if (failures) return 1;
  printf("ok\n");
  return 0;
}
