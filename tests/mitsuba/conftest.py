"""What the Mitsuba 3 tests share: Mitsuba in a spectral variant with spectralize's plugins
registered, scenes whose integrand is deterministic but for the wavelengths (a flat quad seen
head-on by an orthographic camera, lit by a constant environment, sampled by the cosine of a
diffuse BSDF), images written by the tests, and an independent colorimetry oracle from the
project's CSV tables (NumPy, 1 nm, never the library's weights)."""
import os
import pathlib

import numpy as np
import pytest

SOURCE = pathlib.Path(__file__).resolve().parents[2]
DATA = SOURCE / "data"
IMAGES = SOURCE / "testimages"
EXE = os.environ.get("SPECTRALIZE_EXE", str(SOURCE / "build" / "spectralize"))

os.environ.pop("OCIO", None)  # the shipped config, whatever the environment says


@pytest.fixture(scope="session")
def mi():
    mitsuba = pytest.importorskip("mitsuba")
    use(mitsuba, "llvm_ad_spectral")
    return mitsuba


def use(mitsuba, variant):
    """Sets `variant` and, for a spectral one, registers spectralize's plugins for it."""
    import spectralize.mitsuba
    mitsuba.set_variant(variant)
    if "spectral" in variant:
        spectralize.mitsuba.register()


def write_image(path, pixels, dtype="float", colorspace=None):
    """An image of (H, W, C) pixels by OpenImageIO (float, half or uint8 samples as given)."""
    import OpenImageIO as oiio
    pixels = np.ascontiguousarray(pixels)
    h, w, c = pixels.shape
    spec = oiio.ImageSpec(w, h, c, dtype)
    if colorspace:
        spec.attribute("oiio:ColorSpace", colorspace)
    out = oiio.ImageOutput.create(str(path))
    assert out.open(str(path), spec), oiio.geterror()
    assert out.write_image(pixels), out.geterror()
    out.close()


def srgb_encode(linear):
    """IEC 61966-2-1's curve, to 8 bits."""
    x = np.clip(linear, 0.0, 1.0)
    v = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
    return np.round(v * 255).astype(np.uint8)


def srgb_decode(code):
    v = np.asarray(code, dtype=np.float64) / 255
    return np.where(v <= 0.04045, v / 12.92, np.power((v + 0.055) / 1.055, 2.4))


def flat_quad(mitsuba, texture, width, height, per_texel=2, spp=1024, sampler="independent",
              light=None, seed=1, bsdf=None):
    """The texture on a quad filling an orthographic camera's view, one texel per per_texel^2
    pixels, lit by a constant environment (`light`: a spectrum dict; default Mitsuba's d65),
    by a `direct` integrator sampling only the diffuse BSDF (cosine-distributed: every sample
    sees the light; `bsdf`, another BSDF dict, replaces it); returns each texel's mean linear
    Rec.709 RGB, (height, width, 3), row 0 at the texture's top."""
    scene = mitsuba.load_dict({
        "type": "scene",
        "integrator": {"type": "direct", "emitter_samples": 0, "bsdf_samples": 1},
        "sensor": {
            "type": "orthographic",
            "to_world": mitsuba.ScalarTransform4f().look_at(origin=[0, 0, 1], target=[0, 0, 0],
                                                             up=[0, 1, 0]),
            "film": {"type": "hdrfilm", "width": width * per_texel,
                     "height": height * per_texel, "rfilter": {"type": "box"},
                     "pixel_format": "rgb"},
            "sampler": {"type": sampler, "sample_count": spp}},
        "quad": {"type": "rectangle",
                 "to_world": mitsuba.ScalarTransform4f().scale([1, height / width, 1]),
                 "bsdf": bsdf or {"type": "diffuse", "reflectance": texture}},
        "light": {"type": "constant", "radiance": light or {"type": "d65"}}})
    img = np.array(mitsuba.render(scene, seed=seed), dtype=np.float64)
    # The rectangle's v runs up the image, the texture's rows down: texel row 0 is at the bottom.
    return img.reshape(height, per_texel, width, per_texel, 3).mean(axis=(1, 3))[::-1]


def rms(x):
    return float(np.sqrt(np.mean(np.square(x))))


class Colorimetry:
    """CIE 1931 2° on the 1 nm table (360-830 nm), trapezoids; spectra interpolated linearly,
    measured reflectances held at their end values outside 380-780 nm (CIE 015's advice)."""

    def __init__(self):
        t = np.loadtxt(DATA / "cie1931_2deg_cmf_1nm.csv", delimiter=",", skiprows=1)
        self.nm, self.cmf = t[:, 0], t[:, 1:4]
        self.tau = np.ones_like(self.nm)
        self.tau[0] = self.tau[-1] = 0.5

    def on_grid(self, nm, values):
        return np.interp(self.nm, nm, values)

    def illuminant(self, name):
        """(nm, values) of A, FL2, FL11 or D65 from the project's tables."""
        if name in ("A", "D65"):
            file = "cie_illuminant_a_1nm.csv" if name == "A" else "cie_illuminant_d65_1nm.csv"
            t = np.loadtxt(DATA / file, delimiter=",", skiprows=1)
            return t[:, 0], t[:, 1]
        with open(DATA / "cie_illuminants_fl_hp_led_5nm.csv") as f:
            header = f.readline().strip().split(",")
        t = np.loadtxt(DATA / "cie_illuminants_fl_hp_led_5nm.csv", delimiter=",", skiprows=1)
        return t[:, 0], t[:, header.index(name)]

    def colorchecker(self):
        """The 24 measured reflectances (Ohta), (24, 471) on the 1 nm grid, and their names."""
        with open(DATA / "colorchecker_n_ohta_5nm.csv") as f:
            names = f.readline().strip().split(",")[1:]
        t = np.loadtxt(DATA / "colorchecker_n_ohta_5nm.csv", delimiter=",", skiprows=1)
        return np.stack([self.on_grid(t[:, 0], t[:, 1 + i]) for i in range(24)]), names

    def xyz(self, spectra_1nm):
        return (np.asarray(spectra_1nm) * self.tau) @ self.cmf


COLOUR = Colorimetry()

# IEC 61966-2-1's matrices (linear Rec.709 <-> XYZ, D65).
RGB_TO_XYZ = np.array([[0.4124564, 0.3575761, 0.1804375],
                       [0.2126729, 0.7151522, 0.0721750],
                       [0.0193339, 0.1191920, 0.9503041]])


def lab(xyz, white):
    """CIELAB of XYZ relative to `white`."""
    t = np.asarray(xyz, dtype=np.float64) / white
    f = np.where(t > (6 / 29) ** 3, np.cbrt(t), t / (3 * (6 / 29) ** 2) + 4 / 29)
    return np.stack([116 * f[..., 1] - 16, 500 * (f[..., 0] - f[..., 1]),
                     200 * (f[..., 1] - f[..., 2])], axis=-1)


def delta_e2000(lab1, lab2):
    """CIEDE2000 (Sharma, Wu & Dalal 2005)."""
    L1, a1, b1 = np.moveaxis(np.asarray(lab1, dtype=np.float64), -1, 0)
    L2, a2, b2 = np.moveaxis(np.asarray(lab2, dtype=np.float64), -1, 0)
    C1, C2 = np.hypot(a1, b1), np.hypot(a2, b2)
    Cm = (C1 + C2) / 2
    G = 0.5 * (1 - np.sqrt(Cm ** 7 / (Cm ** 7 + 25.0 ** 7)))
    a1p, a2p = (1 + G) * a1, (1 + G) * a2
    C1p, C2p = np.hypot(a1p, b1), np.hypot(a2p, b2)
    h1p = np.degrees(np.arctan2(b1, a1p)) % 360
    h2p = np.degrees(np.arctan2(b2, a2p)) % 360
    dLp, dCp = L2 - L1, C2p - C1p
    dh = h2p - h1p
    dh = np.where(C1p * C2p == 0, 0, np.where(dh > 180, dh - 360, np.where(dh < -180, dh + 360, dh)))
    dHp = 2 * np.sqrt(C1p * C2p) * np.sin(np.radians(dh / 2))
    Lmp, Cmp = (L1 + L2) / 2, (C1p + C2p) / 2
    hs = h1p + h2p
    hmp = np.where(C1p * C2p == 0, hs,
                   np.where(np.abs(h1p - h2p) <= 180, hs / 2,
                            np.where(hs < 360, (hs + 360) / 2, (hs - 360) / 2)))
    T = (1 - 0.17 * np.cos(np.radians(hmp - 30)) + 0.24 * np.cos(np.radians(2 * hmp))
         + 0.32 * np.cos(np.radians(3 * hmp + 6)) - 0.20 * np.cos(np.radians(4 * hmp - 63)))
    dtheta = 30 * np.exp(-(((hmp - 275) / 25) ** 2))
    Rc = 2 * np.sqrt(Cmp ** 7 / (Cmp ** 7 + 25.0 ** 7))
    Sl = 1 + 0.015 * (Lmp - 50) ** 2 / np.sqrt(20 + (Lmp - 50) ** 2)
    Sc, Sh = 1 + 0.045 * Cmp, 1 + 0.015 * Cmp * T
    Rt = -np.sin(np.radians(2 * dtheta)) * Rc
    return np.sqrt((dLp / Sl) ** 2 + (dCp / Sc) ** 2 + (dHp / Sh) ** 2
                   + Rt * (dCp / Sc) * (dHp / Sh))
