// The definitions of spectralize::rt (<spectralize/rt.h>'s C API and what <spectralize/rt.hpp>
// does not define inline: include/spectralize/rt_impl.hpp) for this program: the one
// translation unit that asks for them.
#define SPECTRALIZE_RT_IMPLEMENTATION
#include <spectralize/rt.h>
