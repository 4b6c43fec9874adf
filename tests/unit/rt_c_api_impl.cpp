// The C API's definitions for rt_c_api_test.c: the one C++ translation unit that defines
// SPECTRALIZE_RT_IMPLEMENTATION (include/spectralize/rt.h, rt_impl.hpp). The header is included
// first without it, as a renderer's own header would (pbrt's spectrum.h): the define still works.
#include <spectralize/rt.h>
#define SPECTRALIZE_RT_IMPLEMENTATION
#include <spectralize/rt.h>
