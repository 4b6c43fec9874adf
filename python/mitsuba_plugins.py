"""Mitsuba 3 plugins that render spectralize's exact spectra (spectral variants).

    import mitsuba as mi
    mi.set_variant("llvm_ad_spectral")      # or scalar_spectral, cuda_ad_spectral
    import spectralize.mitsuba
    spectralize.mitsuba.register()

then, in a scene (dict or XML):

- texture ``spectralize_rgb``: an RGB image file (``filename``: anything OpenImageIO reads, its
  colour space decided as the spectralize CLI decides it, or given with ``colorspace``) or a
  constant ``color``, uplifted through a spectralize render-time table (``table``: a .spztab
  file, or made on first use with ``mode``, ``model`` and ``wavelengths`` and kept in ``cache``).
  ``filter_type`` bilinear (default) or nearest, ``wrap_mode`` repeat (default), mirror or
  clamp, ``to_uv``: as Mitsuba's ``bitmap``.
- texture ``spectral_bitmap``: a spectral OpenEXR as spectralize writes it (reflective ``T.*``
  or emissive ``S0.*`` bands), linear between its bands and 0 outside them, bilinear in uv.
- emitter ``spectral_envmap``: a spectral environment map (spectralize's output of an HDRI),
  importance-sampled by luminance as Mitsuba's ``envmap``, with ``scale`` and ``to_world``.

Filtering happens on spectra: each texel's exact spectrum is kept as the blend it is (up to four
of the table's spectra and their weights), and a bilinear lookup blends the four texels'
spectra. Colour is linear in the spectrum, so the filtered spectrum reproduces the filtered
RGB exactly (what Mitsuba's bitmap does with its sigmoid spectra, which are not exact), and a
blend of reflectances in [0, 1] stays in [0, 1]. In the JIT variants every lookup is Dr.Jit
arithmetic and gathers on arrays the plugin holds: no Python runs per sample.
"""

import hashlib
import math
import os
import warnings

_SPECTRAL_HELP = ("mi.set_variant('llvm_ad_spectral') (or 'scalar_spectral', "
                  "'cuda_ad_spectral') before spectralize.mitsuba.register()")


def _mitsuba():
    try:
        import drjit as dr
        import mitsuba as mi
    except ImportError as e:
        raise ImportError(
            "spectralize.mitsuba needs Mitsuba 3 and Dr.Jit (pip install mitsuba==3.9.1 "
            "drjit==1.5.0; make test installs them into the project's virtual environment): "
            + str(e)) from e
    return mi, dr


def _core():
    import spectralize
    return spectralize


def register():
    """register() -> None

    Registers spectralize_rgb, spectral_bitmap and spectral_envmap with Mitsuba for the active
    variant, which must be a spectral one (RuntimeError naming it otherwise, or when none is
    set). Call it again after switching variants. Cost: O(1)."""
    mi, dr = _mitsuba()
    variant = mi.variant()
    if variant is None:
        raise RuntimeError("spectralize.mitsuba.register(): no Mitsuba variant is set: "
                           + _SPECTRAL_HELP)
    if "spectral" not in variant:
        raise RuntimeError(
            "spectralize.mitsuba.register(): the active Mitsuba variant '%s' renders %s, not "
            "spectra: %s" % (variant, "RGB" if "rgb" in variant else "one band", _SPECTRAL_HELP))
    classes = _plugin_classes(mi, dr)
    mi.register_texture("spectralize_rgb", lambda props: classes["spectralize_rgb"](props))
    mi.register_texture("spectral_bitmap", lambda props: classes["spectral_bitmap"](props))
    mi.register_emitter("spectral_envmap", lambda props: classes["spectral_envmap"](props))


# --- What the plugins share, independent of Mitsuba --------------------------------------------

def _cache_folder(given):
    if given:
        return os.fspath(given)
    base = os.environ.get("SPECTRALIZE_CACHE") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache"),
        "spectralize")
    return os.path.join(base, "tables")


def _config_identity(config):
    """The OCIO config by its content (a path, $OCIO, or the shipped one)."""
    path = config or os.environ.get("OCIO") or ""
    if not path:
        return "shipped"
    if path.startswith("ocio://"):
        return path
    try:
        with open(path, "rb") as f:
            return path + ":" + hashlib.sha256(f.read()).hexdigest()
    except OSError:
        return path


def table_for(colorspace, mode, model=None, wavelengths="360:830:5", config=None, cache=None,
              observer="cie1931_mitsuba"):
    """table_for(colorspace, mode, model=None, wavelengths='360:830:5', config=None, cache=None,
    observer='cie1931_mitsuba') -> path

    The render-time table of exact spectra of a linear colour space, as `spectralize table`
    makes it, made on first use and kept in `cache` (default: $SPECTRALIZE_CACHE/tables, else
    ~/.cache/spectralize/tables), named by everything it depends on (spectralize's version,
    the colour space, mode, model, wavelengths, observer and the config's content). Mitsuba
    samples 360-830 nm and integrates the CIE 1931 functions at their 5 nm points, linear
    between them: hence the defaults, with which a colour reproduces as Mitsuba's film sees
    it. Cost: a few seconds the first time, a file check after."""
    sp = _core()
    key = "\n".join([sp.__version__, colorspace, mode, model or "", wavelengths, observer,
                     _config_identity(config)])
    folder = _cache_folder(cache)
    os.makedirs(folder, exist_ok=True)
    path = os.path.join(folder, "spectralize-%s.spztab" % hashlib.sha256(key.encode()).hexdigest()[:24])
    if not os.path.isfile(path):
        options = {"colorspace": colorspace, "mode": mode, "wavelengths": wavelengths,
                   "observer": observer}
        if model:
            options["model"] = model
        if config:
            options["config"] = config
        sp.table(path, **options)  # written atomically: concurrent first uses are safe
    return path


def read_spectral_exr(path):
    """read_spectral_exr(path) -> (values (H, W, N) float32, wavelengths (N,) float64, kind)

    The spectral bands of an OpenEXR in the layout spectralize writes (Fichet et al. 2021):
    reflective 'T.<nm>nm' (kind 'reflectance') or emissive 'S0.<nm>nm' (kind 'emission')
    channels, decimal comma or point, in order of wavelength. OSError names the file and why.
    Cost: reading the file, O(pixels x N)."""
    import numpy as np
    import OpenImageIO as oiio
    inp = oiio.ImageInput.open(os.fspath(path))
    if inp is None:
        raise OSError("'%s': cannot be read: %s" % (path, oiio.geterror()))
    try:
        spec = inp.spec()
        bands = {"T": [], "S0": []}
        for i, name in enumerate(spec.channelnames):
            head, _, rest = name.partition(".")
            if head in bands and rest.endswith("nm"):
                try:
                    bands[head].append((float(rest[:-2].replace(",", ".")), i))
                except ValueError:
                    continue
        kind = "reflectance" if bands["T"] else "emission" if bands["S0"] else None
        if kind is None:
            raise OSError("'%s': no spectral bands (channels T.<nm>nm or S0.<nm>nm): it is not "
                          "a spectral OpenEXR (make one with `spectralize IMAGE -o OUT.exr`)" % path)
        chosen = sorted(bands["T" if kind == "reflectance" else "S0"])
        if len(chosen) < 2:
            raise OSError("'%s': one spectral band only" % path)
        pixels = inp.read_image(0, 0, 0, spec.nchannels, "float")
        if pixels is None:
            raise OSError("'%s': cannot be read: %s" % (path, inp.geterror() or oiio.geterror()))
    finally:
        inp.close()
    pixels = np.asarray(pixels, dtype=np.float32).reshape(spec.height, spec.width, spec.nchannels)
    values = np.ascontiguousarray(pixels[:, :, [i for _, i in chosen]])
    if not np.all(np.isfinite(values)):
        raise OSError("'%s': NaN or infinite samples" % path)
    return values, np.array([nm for nm, _ in chosen], dtype=np.float64), kind


def texel_rgb(values, wavelengths, kind):
    """The linear Rec.709 RGB of spectra (..., N) sampled at wavelengths (N,), by spectralize's
    reference integration (a reflectance under the illuminant, white balanced): what a
    spectral texture's eval_3, eval_1 and mean report, and what an environment map is sampled
    by. Cost: O(values)."""
    import numpy as np
    sp = _core()
    flat = np.ascontiguousarray(values, dtype=np.float32).reshape(-1, len(wavelengths))
    rgb = sp.to_rgb(flat, np.asarray(wavelengths, dtype=np.float64), mode=kind,
                    colorspace="Linear Rec.709 (sRGB)")
    return rgb.reshape(tuple(values.shape[:-1]) + (3,))


# --- The plugins ------------------------------------------------------------------------------

def _plugin_classes(mi, dr):
    import numpy as np

    jit = dr.is_jit_v(mi.Float)
    UInt32, Float = mi.UInt32, mi.Float

    def gather_f(array, index, active=True):
        if jit:
            return dr.gather(Float, array, index, active)
        return float(array[int(index)]) if active else 0.0

    def gather_vec(kind, size, array, index, active=True):
        """`size` consecutive values at array[size * index:]: one gather in JIT variants."""
        if jit:
            return dr.gather(kind, array, index, active)
        i = int(index) * size
        return [array[i + j] for j in range(size)] if active else [0] * size

    def held_f(values):
        values = np.ascontiguousarray(values, dtype=np.float32).ravel()
        return Float(values) if jit else values

    def held_u(values):
        values = np.ascontiguousarray(values, dtype=np.uint32).ravel()
        return UInt32(values) if jit else values

    class Spectra:
        """The rows of a matrix of spectra (M, N): a row's value between bands k and k + 1 is
        two gathers and a lerp."""

        def __init__(self, matrix):
            m = np.asarray(matrix, dtype=np.float32)
            self.intervals = m.shape[1]
            self.data = held_f(m)

        def value(self, row, k, f, active=True):
            i = row * self.intervals + k
            a, b = gather_f(self.data, i, active), gather_f(self.data, i + 1, active)
            return a + f * (b - a)

    def floor_i(x):
        return mi.Int32(dr.floor(x)) if jit else int(math.floor(x))

    def wrap(i, n, mode):
        if mode == "clamp":
            return dr.clip(i, 0, n - 1) if jit else min(max(i, 0), n - 1)
        if mode == "mirror":
            if jit:
                i = dr.select(i < 0, -i - 1, i) % (2 * n)
                return dr.select(i >= n, 2 * n - i - 1, i)
            i = (-i - 1 if i < 0 else i) % (2 * n)
            return 2 * n - i - 1 if i >= n else i
        return i % n if not jit else dr.select(i % n < 0, i % n + n, i % n)

    class Image:
        """Texel addressing of a width x height image as Mitsuba's bitmap addresses it: uv
        (0, 0) is the top-left corner, texel centres at half-integers, wrapped per texel."""

        def __init__(self, width, height, filter_type, wrap_mode, to_uv):
            if filter_type not in ("bilinear", "nearest"):
                raise ValueError("filter_type '%s' (valid: bilinear, nearest)" % filter_type)
            if wrap_mode not in ("repeat", "mirror", "clamp"):
                raise ValueError("wrap_mode '%s' (valid: repeat, mirror, clamp)" % wrap_mode)
            self.width, self.height = width, height
            self.filter, self.wrap = filter_type, wrap_mode
            # A 2-D affine map of uv (Mitsuba keeps it as a 4 x 4 matrix: rows u, v, with the
            # translation in the last column).
            self.to_uv = None
            if to_uv is not None:
                m = np.array(to_uv.matrix, dtype=np.float64).reshape(4, 4)
                self.to_uv = tuple(float(x) for x in (m[0, 0], m[0, 1], m[0, 3], m[1, 0],
                                                      m[1, 1], m[1, 3]))

        def taps(self, uv):
            """The texels at uv and their weights: [(index, weight)], one or four."""
            if self.to_uv is not None:
                a, b, c, d, e, f = self.to_uv
                uv = (a * uv[0] + b * uv[1] + c, d * uv[0] + e * uv[1] + f)
            w, h = self.width, self.height
            if self.filter == "nearest":
                x = wrap(floor_i(uv[0] * w), w, self.wrap)
                y = wrap(floor_i(uv[1] * h), h, self.wrap)
                return [(UInt32(y * w + x) if jit else y * w + x, 1.0)]
            px, py = uv[0] * w - 0.5, uv[1] * h - 0.5
            fx, fy = dr.floor(px) if jit else math.floor(px), dr.floor(py) if jit else math.floor(py)
            ax, ay = px - fx, py - fy
            x0, y0 = floor_i(px), floor_i(py)
            xs = (wrap(x0, w, self.wrap), wrap(x0 + 1, w, self.wrap))
            ys = (wrap(y0, h, self.wrap), wrap(y0 + 1, h, self.wrap))
            out = []
            for j, wy in ((0, 1 - ay), (1, ay)):
                for i, wx in ((0, 1 - ax), (1, ax)):
                    index = ys[j] * w + xs[i]
                    out.append((UInt32(index) if jit else index, wx * wy))
            return out

    class Bands:
        """Where a wavelength falls among bands: regular grids by arithmetic, others by a
        search; 0 outside [first, last] (spectralize's spectra are 0 outside their samples)."""

        def __init__(self, wavelengths):
            nm = np.asarray(wavelengths, dtype=np.float64)
            self.count = len(nm)
            self.first, self.last = float(nm[0]), float(nm[-1])
            self.step = (self.last - self.first) / (self.count - 1)
            self.regular = bool(np.all(np.abs(np.diff(nm) - self.step) <= 1e-6 * self.step))
            self.nm = held_f(nm)

        def locate(self, lam):
            """(k, f, inside): the interval [k, k + 1] and the fraction f within it."""
            n = self.count
            inside = (lam >= self.first) & (lam <= self.last)
            if self.regular:
                t = (lam - self.first) * (1.0 / self.step)
                t = dr.clip(t, 0, n - 1) if jit else min(max(t, 0.0), n - 1.0)
                k = dr.minimum(UInt32(t), n - 2) if jit else min(int(t), n - 2)
                return k, t - k, inside
            if jit:
                k = dr.binary_search(0, n - 2, lambda i: dr.gather(Float, self.nm, i + 1) < lam)
            else:
                k = min(max(int(np.searchsorted(self.nm, lam, side="right")) - 1, 0), n - 2)
            a, b = gather_f(self.nm, k), gather_f(self.nm, k + 1)
            f = (lam - a) / (b - a)
            return k, dr.clip(f, 0, 1) if jit else min(max(f, 0.0), 1.0), inside

    def spectral_lanes(si):
        lam = si.wavelengths
        return [lam[i] for i in range(len(lam))]

    def make_spectrum(values):
        return mi.UnpolarizedSpectrum(*values)

    def luminance(rgb):
        return 0.212671 * rgb[0] + 0.715160 * rgb[1] + 0.072169 * rgb[2]  # as mi.luminance()

    # XYZ (D65) -> linear Rec.709, the RGB of Mitsuba's eval_3 (IEC 61966-2-1).
    xyz_to_709 = np.array([[3.2404542, -1.5371385, -0.4985314],
                           [-0.9692660, 1.8760108, 0.0415560],
                           [0.0556434, -0.2040259, 1.0572252]])

    def props_get(props, key, default=None):
        return props[key] if key in props else default

    class SpectralizeRGB(mi.Texture):
        def __init__(self, props):
            mi.Texture.__init__(self, props)
            sp = _core()
            filename = props_get(props, "filename")
            color = props_get(props, "color")
            if (filename is None) == (color is None):
                raise ValueError("spectralize_rgb: give a filename or a color (one of them)")
            self.mode = props_get(props, "mode", "reflectance")
            if self.mode not in ("reflectance", "emission"):
                raise ValueError("spectralize_rgb: mode '%s' (valid: reflectance, emission)"
                                 % self.mode)
            colorspace = props_get(props, "colorspace")
            config = props_get(props, "config")
            if filename is not None:
                options = {"mode": self.mode}
                if colorspace:
                    options["colorspace"] = colorspace
                if config:
                    options["config"] = config
                rgb, info = sp.read_rgb(filename, **options)
                for w in info["warnings"]:
                    warnings.warn(w, sp.SpectralizeWarning, stacklevel=2)
                space = info["linear_colorspace"]
                self.source = "'%s' (%s, %s)" % (filename, info["colorspace"],
                                                 info["colorspace_reason"])
            else:
                rgb = np.array(color, dtype=np.float32).reshape(1, 1, 3)
                space = colorspace or "scene_linear"
                self.source = "color %s" % list(np.asarray(color, dtype=float))
            table = props_get(props, "table")
            if table is None:
                table = table_for(space, self.mode, props_get(props, "model"),
                                  props_get(props, "wavelengths", "360:830:5"), config,
                                  props_get(props, "cache"),
                                  props_get(props, "observer", "cie1931_mitsuba"))
            self.table_path = os.fspath(table)
            t = sp.rt.Table(self.table_path)
            if t.mode != self.mode:
                raise ValueError("spectralize_rgb: table '%s' is a %s table, the texture's mode "
                                 "is %s" % (self.table_path, t.mode, self.mode))
            if filename is not None and t.colorspace != space:
                raise ValueError("spectralize_rgb: table '%s' is for '%s', the image '%s' is in "
                                 "'%s' (linear): make the table for that space, or leave "
                                 "table= out" % (self.table_path, t.colorspace, filename, space))
            h, w = rgb.shape[0], rgb.shape[1]
            n = len(t.wavelengths)
            # The distinct colours (a palette; each texel's index into it, unless all differ),
            # and each colour's spectrum at the table's bands where they fit in `memory` (MB:
            # two gathers per wavelength and tap), else the blend it is (its rows and weights
            # and the table's spectra blended: four times the gathers, 32 bytes a colour).
            flat = rgb.reshape(-1, 3)
            colours, index = np.unique(flat, axis=0, return_inverse=True)
            self.palette = held_u(index.ravel()) if len(colours) < len(flat) else None
            if self.palette is None:
                colours = flat
            budget = float(props_get(props, "memory", 1024)) * 2 ** 20
            self.blended = len(colours) * n * 4 > budget
            if self.blended:
                rows, weights, samples, counts = t.blend(colours)
                self.rows = held_u(rows)
                self.weights = held_f(weights)
                self.spectra = Spectra(samples)
            else:
                values, counts = t.spectra(colours)
                self.spectra = Spectra(values)
            mapped = counts["mapped"] + counts["invalid"] + counts["negative"]
            if mapped:
                warnings.warn("spectralize_rgb: %s: %d texels out of gamut and mapped (%d invalid, "
                              "%d negative luminance: black)" % (self.source, mapped,
                                                                 counts["invalid"], counts["negative"]),
                              sp.SpectralizeWarning, stacklevel=2)
            self.image = Image(w, h, props_get(props, "filter_type", "bilinear"),
                               props_get(props, "wrap_mode", "repeat"), props_get(props, "to_uv"))
            self.bands = Bands(t.wavelengths)
            # eval_1 / eval_3 / mean, as the bitmap: the RGB (in Mitsuba's linear Rec.709; a
            # texture of those primaries as it is, others through CIE XYZ).
            to_709 = xyz_to_709 @ t.rgb_to_xyz
            if np.allclose(to_709, np.eye(3), atol=2e-3):
                to_709 = np.eye(3)
            rgb709 = rgb.reshape(-1, 3).astype(np.float64) @ to_709.T
            self.rgb = [held_f(rgb709[:, c]) for c in range(3)]
            self.mean_value = float(np.mean(luminance(rgb709.T)))
            self.max_value = float(np.max(samples if self.blended else values))
            self.colorspace = t.colorspace

        def eval(self, si, active=True):
            k, f, inside = zip(*[self.bands.locate(l) for l in spectral_lanes(si)])
            acc = [0.0] * len(k)
            for index, a in self.image.taps(si.uv):
                if self.palette is not None:
                        index = dr.gather(UInt32, self.palette, index, active) if jit else \
                        int(self.palette[int(index)])
                if not self.blended:
                    for i in range(len(k)):
                        acc[i] = acc[i] + a * self.spectra.value(index, k[i], f[i], active)
                    continue
                rows = gather_vec(mi.Vector4u, 4, self.rows, index, active)
                weights = gather_vec(mi.Vector4f, 4, self.weights, index, active)
                for v in range(4):
                    wv = weights[v] * a
                    for i in range(len(k)):
                        acc[i] = acc[i] + wv * self.spectra.value(rows[v], k[i], f[i], active)
            out = []
            for i in range(len(k)):
                v = dr.minimum(acc[i], 1.0) if self.mode == "reflectance" else acc[i]
                out.append(dr.select(inside[i], v, 0.0) if jit else (v if inside[i] else 0.0))
            return make_spectrum(out)

        def _rgb(self, si, active=True):
            c = [0.0, 0.0, 0.0]
            for index, a in self.image.taps(si.uv):
                for j in range(3):
                    c[j] = c[j] + a * gather_f(self.rgb[j], index, active)
            return c

        def eval_3(self, si, active=True):
            return mi.Color3f(*self._rgb(si, active))

        def eval_1(self, si, active=True):
            return luminance(self._rgb(si, active))

        def mean(self):
            return self.mean_value

        def max(self):
            return self.max_value

        def is_spatially_varying(self):
            return self.image.width * self.image.height > 1

        def resolution(self):
            return mi.ScalarVector2i(self.image.width, self.image.height)

        def traverse(self, callback):
            pass

        def to_string(self):
            return ("SpectralizeRGB[%s, %s, table '%s' (%s), %s%s]"
                    % (self.source, self.mode, self.table_path, self.colorspace,
                       "blends of the table's spectra" if self.blended else "spectra",
                       " of a palette" if self.palette is not None else ""))

    class SpectralBitmap(mi.Texture):
        def __init__(self, props):
            mi.Texture.__init__(self, props)
            filename = props_get(props, "filename")
            if filename is None:
                raise ValueError("spectral_bitmap: filename (a spectral OpenEXR) is required")
            values, nm, self.kind = read_spectral_exr(filename)
            self.filename = os.fspath(filename)
            h, w, n = values.shape
            self.image = Image(w, h, props_get(props, "filter_type", "bilinear"),
                               props_get(props, "wrap_mode", "repeat"), props_get(props, "to_uv"))
            self.bands = Bands(nm)
            self.spectra = Spectra(values.reshape(-1, n))
            rgb = texel_rgb(values, nm, self.kind).reshape(-1, 3).astype(np.float64)
            self.rgb = [held_f(rgb[:, c]) for c in range(3)]
            self.mean_value = float(np.mean(luminance(rgb.T)))
            self.max_value = float(np.max(values))

        def eval(self, si, active=True):
            k, f, inside = zip(*[self.bands.locate(l) for l in spectral_lanes(si)])
            acc = [0.0] * len(k)
            for index, a in self.image.taps(si.uv):
                for i in range(len(k)):
                    acc[i] = acc[i] + a * self.spectra.value(index, k[i], f[i], active)
            return make_spectrum([dr.select(inside[i], acc[i], 0.0) if jit
                                  else (acc[i] if inside[i] else 0.0) for i in range(len(k))])

        _rgb = SpectralizeRGB._rgb
        eval_3 = SpectralizeRGB.eval_3
        eval_1 = SpectralizeRGB.eval_1

        def mean(self):
            return self.mean_value

        def max(self):
            return self.max_value

        def is_spatially_varying(self):
            return True

        def resolution(self):
            return mi.ScalarVector2i(self.image.width, self.image.height)

        def traverse(self, callback):
            pass

        def to_string(self):
            return "SpectralBitmap['%s', %s, %d bands]" % (self.filename, self.kind,
                                                          self.bands.count)

    class SpectralEnvmap(mi.Emitter):
        """A latitude-longitude map of spectra, addressed, interpolated and sampled as Mitsuba's
        envmap addresses, interpolates and samples its RGB: row 0 is the direction +y, pixels
        are the grid's nodes (a last column repeats the first), bilinear between them, and
        directions are drawn in proportion to luminance x sin(theta)."""

        def __init__(self, props):
            mi.Emitter.__init__(self, props)
            filename = props_get(props, "filename")
            if filename is None:
                raise ValueError("spectral_envmap: filename (a spectral OpenEXR) is required")
            values, nm, kind = read_spectral_exr(filename)
            self.filename = os.fspath(filename)
            if kind != "emission":
                raise ValueError("spectral_envmap: '%s' holds reflectances (T.* bands), not light: "
                                 "spectralize it as light (--mode emission)" % self.filename)
            h, w, n = values.shape
            if w < 2 or h < 3:
                raise ValueError("spectral_envmap: '%s' is %dx%d; an environment map is at least "
                                 "2x3 pixels" % (self.filename, w, h))
            self.scale = float(props_get(props, "scale", 1.0))
            to_world = props_get(props, "to_world")
            self.to_world = mi.Transform4f(mi.ScalarTransform4f(
                np.array(to_world.matrix, dtype=np.float32).reshape(4, 4))) \
                if to_world is not None else mi.Transform4f()
            # The periodic column, as Mitsuba's envmap adds it.
            values = np.concatenate([values, values[:, :1, :]], axis=1)
            self.res = (w + 1, h)
            self.bands = Bands(nm)
            self.spectra = Spectra(values.reshape(-1, n))
            lum = luminance(texel_rgb(values, nm, kind).reshape(-1, 3).T.astype(np.float64))
            lum = np.maximum(lum.reshape(h, w + 1), 0.0)
            sin_theta = np.sin(np.arange(h) * (math.pi / (h - 1)))
            self.warp = mi.Hierarchical2D0(np.ascontiguousarray(lum * sin_theta[:, None],
                                                                dtype=np.float32))
            self.half_texel = 0.5 / w
            self.bsphere_center = mi.Point3f(0.0)
            self.bsphere_radius = mi.Float(1.0)
            self.m_flags = mi.EmitterFlags.Infinite | mi.EmitterFlags.SpatiallyVarying

        def set_scene(self, scene):
            box = scene.bbox()
            if box.valid():
                sphere = box.bounding_sphere()
                self.bsphere_center = mi.Point3f(sphere.center)
                self.bsphere_radius = mi.Float(max(1e-4, sphere.radius * (1 + 1e-4)))
            else:
                self.bsphere_center = mi.Point3f(0.0)
                self.bsphere_radius = mi.Float(1e-4)

        def _spectrum(self, uv, wavelengths, active=True):
            w, h = self.res
            u = uv[0] - self.half_texel
            v = uv[1]
            u = (u - dr.floor(u)) * (w - 1)
            v = (v - dr.floor(v)) * (h - 1)
            x = dr.minimum(UInt32(u), w - 2) if jit else min(int(u), w - 2)
            y = dr.minimum(UInt32(v), h - 2) if jit else min(int(v), h - 2)
            ax, ay = u - x, v - y
            lanes = [wavelengths[i] for i in range(len(wavelengths))]
            k, f, inside = zip(*[self.bands.locate(l) for l in lanes])
            acc = [0.0] * len(lanes)
            for dy, wy in ((0, 1 - ay), (1, ay)):
                for dx, wx in ((0, 1 - ax), (1, ax)):
                    pixel = (y + dy) * w + x + dx
                    for i in range(len(lanes)):
                        acc[i] = acc[i] + wx * wy * self.spectra.value(pixel, k[i], f[i], active)
            return make_spectrum([(dr.select(inside[i], acc[i], 0.0) if jit
                                   else (acc[i] if inside[i] else 0.0)) * self.scale
                                  for i in range(len(lanes))])

        @staticmethod
        def _direction(uv):
            theta, phi = uv[1] * math.pi, uv[0] * (2 * math.pi)
            st, ct = dr.sincos(theta)
            sp_, cp = dr.sincos(phi)
            return mi.Vector3f(sp_ * st, ct, -cp * st), dr.rcp(dr.maximum(st, 1e-7))

        @staticmethod
        def _uv(d):
            return mi.Point2f(dr.atan2(d[0], -d[2]) * (0.5 / math.pi),
                              dr.safe_acos(d[1]) * (1 / math.pi))

        def eval(self, si, active=True):
            d = self.to_world.inverse() @ (-si.wi)
            return self._spectrum(self._uv(d), si.wavelengths, active)

        def sample_direction(self, it, sample, active=True):
            uv, pdf = self.warp.sample(sample, active=active)
            uv = mi.Point2f(uv[0] + self.half_texel, uv[1])
            active = active & (pdf > 0)
            d, inv_sin = self._direction(uv)
            radius = dr.maximum(self.bsphere_radius, dr.norm(it.p - self.bsphere_center))
            dist = 2 * radius
            d = self.to_world @ d
            ds = dr.zeros(mi.DirectionSample3f)
            ds.p = it.p + d * dist
            ds.n = -d
            ds.uv = uv
            ds.time = it.time
            ds.pdf = dr.select(active, pdf * inv_sin * (1 / (2 * math.pi * math.pi)), 0.0)
            ds.delta = False
            ds.emitter = mi.EmitterPtr(self)
            ds.d = d
            ds.dist = dist
            weight = self._spectrum(uv, it.wavelengths, active) / dr.select(active, ds.pdf, 1.0)
            return ds, dr.select(active, weight, 0.0)

        def pdf_direction(self, it, ds, active=True):
            d = self.to_world.inverse() @ ds.d
            uv = self._uv(d)
            u = uv[0] - self.half_texel
            uv = mi.Point2f(u - dr.floor(u), uv[1])
            inv_sin = dr.rsqrt(dr.maximum(d[0] * d[0] + d[2] * d[2], 1e-14))
            return self.warp.eval(uv, active=active) * inv_sin * (1 / (2 * math.pi * math.pi))

        def eval_direction(self, it, ds, active=True):
            return self._spectrum(ds.uv, it.wavelengths, active)

        def sample_wavelengths(self, si, sample, active=True):
            wavelengths, weight = mi.sample_rgb_spectrum(mi.sample_shifted(sample))
            return wavelengths, weight * self._spectrum(si.uv, wavelengths, active) / self.scale

        def sample_ray(self, time, wavelength_sample, sample2, sample3, active=True):
            offset = mi.warp.square_to_uniform_disk_concentric(sample2)
            uv, pdf = self.warp.sample(sample3, active=active)
            uv = mi.Point2f(uv[0] + self.half_texel, uv[1])
            active = active & (pdf > 0)
            d, inv_sin = self._direction(uv)
            pdf = pdf * inv_sin * (1 / (2 * math.pi * math.pi))
            d_world = self.to_world @ (-d)
            perpendicular = mi.Frame3f(d).to_world(mi.Vector3f(offset[0], offset[1], 0))
            origin = self.bsphere_center + (perpendicular - d_world) * self.bsphere_radius
            si = dr.zeros(mi.SurfaceInteraction3f)
            si.time = time
            si.p = origin
            si.uv = uv
            wavelengths, weight = mi.sample_rgb_spectrum(mi.sample_shifted(wavelength_sample))
            weight = weight * self._spectrum(uv, wavelengths, active)
            ray = mi.Ray3f(origin, d_world, time, wavelengths)
            weight = weight * (math.pi * self.bsphere_radius * self.bsphere_radius) / \
                dr.select(active, pdf, 1.0)
            return ray, dr.select(active, weight, 0.0)

        def sample_position(self, time, sample, active=True):
            return dr.zeros(mi.PositionSample3f), dr.nan

        def bbox(self):
            return mi.ScalarBoundingBox3f()

        def traverse(self, callback):
            pass

        def to_string(self):
            return "SpectralEnvmap['%s', %dx%d, %d bands, scale %g]" % (
                self.filename, self.res[0] - 1, self.res[1], self.bands.count, self.scale)

    return {"spectralize_rgb": SpectralizeRGB, "spectral_bitmap": SpectralBitmap,
            "spectral_envmap": SpectralEnvmap}
