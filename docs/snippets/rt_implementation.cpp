// The C functions of <spectralize/rt.h>, and the loader behind <spectralize/rt.hpp>, are defined
// in exactly one C++ translation unit of the program; every other C or C++ file just includes
// the header.
#define SPECTRALIZE_RT_IMPLEMENTATION
#include <spectralize/rt.h>
