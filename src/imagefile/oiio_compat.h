#pragma once
// Where OpenImageIO 2.4 (Debian 12) and 3.x (the VFX Reference Platform CY2026) differ, decided
// here once (docs/DESIGN.md §11); the rest of the code names these, never OIIO_VERSION.

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/oiioversion.h>

namespace spectralize {

namespace oiio_compat {

/// TIFF's zip takes a level (zip:1 to zip:9) through OIIO 2.x; OIIO 3 compresses TIFF strips
/// itself at one level whatever is asked (measured with 3.1).
inline constexpr bool kTiffZipLevels = OIIO_VERSION < OIIO_MAKE_VERSION(3, 0, 0);

/// OIIO 3's HEIF writer keeps uint16 samples (as 10 or 12 bits); OIIO 2.4's makes them uint8.
inline constexpr bool kHeifHoldsUint16 = OIIO_VERSION >= OIIO_MAKE_VERSION(3, 0, 0);

/// OIIO 3's PNM writer keeps uint16 (16-bit PPM) and float (PFM) samples; OIIO 2.4's only uint8.
inline constexpr bool kPnmHoldsUint16AndFloat = OIIO_VERSION >= OIIO_MAKE_VERSION(3, 0, 0);

/// OIIO 3 names colour spaces by their interop ID in oiio:ColorSpace ("lin_ap1_scene") and
/// derives it from a PNG's or TIFF's colour chunks and tags when reading; OIIO 2.x keeps the
/// name it was given and says "Linear" or "sRGB" otherwise.
inline constexpr bool kInteropColourSpaceNames = OIIO_VERSION >= OIIO_MAKE_VERSION(3, 0, 0);

}  // namespace oiio_compat

/// `src` averaged over boxes onto `roi` (each output pixel the mean of the input pixels under
/// it: a box filter one output pixel wide). Cost: O(input pixels).
OIIO::ImageBuf box_resize(const OIIO::ImageBuf& src, OIIO::ROI roi);

}  // namespace spectralize

// The qualifier of an IOProxy::flush override: OIIO 3 made Filesystem::IOProxy::flush() a
// non-const virtual (2.x: `virtual void flush() const`).
#if OIIO_VERSION < OIIO_MAKE_VERSION(3, 0, 0)
#define SPECTRALIZE_IOPROXY_FLUSH_CONST const
#else
#define SPECTRALIZE_IOPROXY_FLUSH_CONST
#endif
