#include "rgb2spec_c.h"

#include <math.h>

/* The last k in [0, res - 2] with scale[k] <= z: binary search. */
static int find_interval(const float* scale, int res, float z) {
  int left = 0, size = res - 2;
  while (size > 0) {
    const int half = size >> 1, middle = left + half + 1;
    if (scale[middle] <= z) {
      left = middle;
      size -= half + 1;
    } else {
      size = half;
    }
  }
  return left;
}

void rgb2spec_c_fetch(const rgb2spec_c* model, const float rgb[3], float out[3]) {
  const int res = model->res;
  int i = 0;
  for (int j = 1; j < 3; ++j)
    if (rgb[j] >= rgb[i]) i = j;
  const float z = rgb[i], scale = (float)(res - 1) / z;
  const float x = rgb[(i + 1) % 3] * scale, y = rgb[(i + 2) % 3] * scale;
  const int xi = x < (float)(res - 2) ? (int)x : res - 2;
  const int yi = y < (float)(res - 2) ? (int)y : res - 2;
  const int zi = find_interval(model->scale, res, z);
  const long dx = 3, dy = 3L * res, dz = 3L * res * res;
  const long offset = (((long)(i * res + zi) * res + yi) * res + xi) * 3;
  const float x1 = x - (float)xi, x0 = 1.0f - x1;
  const float y1 = y - (float)yi, y0 = 1.0f - y1;
  const float z1 = (z - model->scale[zi]) / (model->scale[zi + 1] - model->scale[zi]);
  const float z0 = 1.0f - z1;
  const float* d = model->data + offset;
  for (int j = 0; j < 3; ++j, ++d)
    out[j] =
        ((d[0] * x0 + d[dx] * x1) * y0 + (d[dy] * x0 + d[dy + dx] * x1) * y1) * z0 +
        ((d[dz] * x0 + d[dz + dx] * x1) * y0 + (d[dz + dy] * x0 + d[dz + dy + dx] * x1) * y1) * z1;
}

float rgb2spec_c_eval_precise(const float c[3], float lambda) {
  const float x = (c[0] * lambda + c[1]) * lambda + c[2];
  const float y = 1.0f / sqrtf(x * x + 1.0f);
  return 0.5f * x * y + 0.5f;
}
