#pragma once
// Hot loops compiled twice, for AVX2 and for baseline x86-64, the better picked at load time
// (GCC's target_clones): one binary, fast on any x86-64 machine. Off under sanitizers and
// fuzzers (SPECTRALIZE_NO_MULTIVERSION): the loader runs the clones' resolvers before the
// sanitizer's runtime is up.

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && \
    !defined(SPECTRALIZE_NO_MULTIVERSION)
#define SPECTRALIZE_MULTIVERSION_AVX2 [[gnu::target_clones("avx2", "default")]]
#define SPECTRALIZE_MULTIVERSION_V3 [[gnu::target_clones("arch=x86-64-v3", "default")]]
#else
#define SPECTRALIZE_MULTIVERSION_AVX2
#define SPECTRALIZE_MULTIVERSION_V3
#endif
