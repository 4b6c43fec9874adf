/* The speed baseline as renderers run it: Jakob & Hanika's table lookup written in plain C from
 * the paper's formulas (the layout of rgb2spec and pbrt-v4: for the largest component's block, a
 * res^3 grid of 3 coefficients indexed [z][y][x], z the largest component on a smoothstep-spaced
 * scale found by binary search, x and y the others divided by it; a trilinear blend; the
 * sigmoid 0.5 + x / (2 sqrt(1 + x^2)) of the quadratic per wavelength), compiled like the
 * original (C, -O3, float, no -ffast-math). The coefficients come from the project's own fit
 * (src/baseline/sigmoid_spectrum.h). */
#ifndef SPECTRALIZE_BENCH_RGB2SPEC_C_H
#define SPECTRALIZE_BENCH_RGB2SPEC_C_H

#ifdef __cplusplus
extern "C" {
#endif

typedef struct rgb2spec_c {
  int res;
  const float* scale; /* res z positions */
  const float* data;  /* 3 blocks x res^3 nodes x 3 coefficients */
} rgb2spec_c;

/* The three coefficients of a linear RGB colour in [0, 1]^3. Cost: O(log res). */
void rgb2spec_c_fetch(const rgb2spec_c* model, const float rgb[3], float out[3]);

/* The sigmoid spectrum of coefficients c at lambda nm (rgb2spec's eval_precise). Cost: O(1). */
float rgb2spec_c_eval_precise(const float c[3], float lambda);

#ifdef __cplusplus
}
#endif

#endif
