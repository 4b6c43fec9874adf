// The definitions of spectralize::rt's C API (<spectralize/rt.h>) for this program: the one
// translation unit that asks for them.
#define SPECTRALIZE_RT_IMPLEMENTATION
#include <spectralize/rt.h>
