// libspectralize_rt: the C API of <spectralize/rt.h>, compiled once into a shared and a static
// library for programs and plug-in hosts that are not C++ (a C renderer, Python's ctypes,
// Blender's add-ons). Built without exceptions and RTTI, allocating with C's own functions, it
// needs nothing at run time but libc and libm; the linker version script (exports.map) keeps
// every symbol but the spz_ functions local. The definitions are those of
// <spectralize/rt_impl.hpp>, which the define below compiles here.
#define SPECTRALIZE_RT_IMPLEMENTATION
#include <spectralize/rt.h>
