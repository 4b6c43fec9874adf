/* Load a table, take the spectrum of a linear RGB colour, evaluate it at a path's wavelengths.
 * Usage: quickstart TABLE.spztab */
#include <spectralize/rt.h>
#include <stdio.h>

int main(int argc, char** argv) {
  char error[512];
  spz_table* table =
      spz_table_load(argc > 1 ? argv[1] : "srgb_reflectance.spztab", error, sizeof error);
  if (!table) {
    fprintf(stderr, "%s\n", error); /* names the file and the reason */
    return 1;
  }
  const float rgb[3] = {0.21f, 0.72f, 0.15f}; /* linear RGB of the table's colour space */
  spz_spectrum s;
  const int status = spz_fetch(table, rgb, &s); /* SPZ_EXACT, SPZ_MAPPED or < 0 */
  const float lambda[4] = {450.0f, 520.0f, 590.0f, 660.0f};
  float value[4];
  spz_eval4(&s, lambda, value);
  printf("%s, status %d: %.4f %.4f %.4f %.4f\n", spz_table_colorspace(table), status, value[0],
         value[1], value[2], value[3]);
  spz_table_free(table);
  return status == SPZ_EXACT ? 0 : 1;
}
