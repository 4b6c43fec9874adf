/* A C99 program against the installed libspectralize_rt: loads a table, fetches an array of
 * colours, and checks by its own trapezoid integration of the installed CIE 1931 and D65 tables
 * (docs/DESIGN.md §3) that a reflectance reproduces its colour under the table's conventions.
 * Prints "ok <relative error>"; exit 1 otherwise.
 * Usage: rt_c_consumer TABLE.spztab CIE1931_CSV D65_CSV */
#include <math.h>
#include <spectralize/rt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define ROWS 601 /* 1 nm rows, at most (the D65 table starts at 300 nm) */

/* A CSV of a wavelength and `columns` values per row. */
static int read_csv(const char* path, int columns, double rows[ROWS][4]) {
  FILE* f = fopen(path, "r");
  char line[512];
  int n = 0;
  if (!f || !fgets(line, sizeof line, f)) return 0;
  while (n < ROWS && fgets(line, sizeof line, f)) {
    char* p = line;
    for (int c = 0; c <= columns; ++c) {
      rows[n][c] = strtod(p, &p);
      if (*p == ',') ++p;
    }
    ++n;
  }
  fclose(f);
  return n;
}

int main(int argc, char** argv) {
  static double cmf[ROWS][4], d65[ROWS][4];
  char error[512];
  if (argc != 4) return 2;
  spz_table* table = spz_table_load(argv[1], error, sizeof error);
  if (!table) {
    printf("FAILED: %s\n", error);
    return 1;
  }
  const int n = read_csv(argv[2], 3, cmf), m = read_csv(argv[3], 1, d65);
  if (n < 400 || m < 400 || spz_table_mode(table) != 1) return 1;
  /* The array API: three colours at every 1 nm wavelength of the CMF table. */
  const float rgb[9] = {0.2f, 0.5f, 0.1f, 0.7f, 0.3f, 0.3f, 0.05f, 0.05f, 0.9f};
  static float lambda[ROWS], out[3 * ROWS];
  int statuses[3];
  size_t counts[4];
  for (int i = 0; i < n; ++i) lambda[i] = (float)cmf[i][0];
  if (spz_fetch_array(table, rgb, 3, lambda, (size_t)n, out, statuses, counts) != (size_t)n ||
      counts[0] != 3)
    return 1;
  double rgb_to_xyz[9], worst = 0;
  spz_table_rgb_to_xyz(table, rgb_to_xyz);
  const double d65w[3] = {0.3127 / 0.3290, 1.0, 0.3583 / 0.3290};
  for (int k = 0; k < 3; ++k) {
    double xyz[3] = {0, 0, 0}, white[3] = {0, 0, 0};
    float start, step;
    spz_table_wavelengths(table, &start, &step);
    const double last = start + step * (double)(spz_table_bands(table) - 1);
    for (int i = 0; i < n; ++i) {
      const double tau = (i == 0 || i + 1 == n) ? 0.5 : 1.0;
      double e = 0;
      for (int j = 0; j < m; ++j)
        if (d65[j][0] == cmf[i][0]) e = d65[j][1];
      const double inside = cmf[i][0] >= start && cmf[i][0] <= last ? 1.0 : 0.0;
      for (int c = 0; c < 3; ++c) {
        xyz[c] += tau * cmf[i][1 + c] * e * out[k * n + i];
        white[c] += tau * cmf[i][1 + c] * e * inside;
      }
    }
    for (int c = 0; c < 3; ++c) {
      const double* r = rgb_to_xyz + 3 * c;
      const double want = (r[0] * rgb[3 * k] + r[1] * rgb[3 * k + 1] + r[2] * rgb[3 * k + 2]) *
                          (white[c] / white[1]) / d65w[c];
      const double err = fabs(xyz[c] / white[1] - want) / 0.5;
      if (err > worst) worst = err;
    }
  }
  /* A zero-initialised spectrum is the zero spectrum. */
  spz_spectrum zero;
  memset(&zero, 0, sizeof zero);
  if (spz_eval(&zero, 550.0f) != 0.0f) return 1;
  printf("%s %s %.3g\n", worst <= 1e-5 ? "ok" : "FAILED", spz_table_colorspace(table), worst);
  spz_table_free(table);
  return worst <= 1e-5 ? 0 : 1;
}
