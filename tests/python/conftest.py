"""Shared fixtures of the Python module's tests: the module from the build tree (PYTHONPATH, set
by CTest), the repository's test images, and an independent colorimetry oracle built from the
project's own CSV tables with NumPy (never the library's weights)."""
import os
import pathlib

import numpy as np
import pytest

SOURCE = pathlib.Path(__file__).resolve().parents[2]
DATA = SOURCE / "data"
IMAGES = SOURCE / "testimages"

# The shipped config, whatever the environment says.
os.environ.pop("OCIO", None)


def _table(name):
    t = np.loadtxt(DATA / name, delimiter=",", skiprows=1)
    return t[:, 0], t[:, 1:]


class Oracle:
    """docs/DESIGN.md §3: the trapezoid rule on the 1 nm CIE tables (360-830 nm) of the
    piecewise-linear spectrum through the samples (zero outside them)."""

    def __init__(self):
        self.nm, self.cmf = _table("cie1931_2deg_cmf_1nm.csv")
        self.tau = np.ones_like(self.nm)
        self.tau[0] = self.tau[-1] = 0.5
        self.K = np.sum(self.tau * self.cmf[:, 1])
        d65_nm, d65 = _table("cie_illuminant_d65_1nm.csv")
        self.d65 = np.interp(self.nm, d65_nm, d65[:, 0])
        # Linear Rec.709 -> XYZ from the primaries and the D65 white (IEC 61966-2-1).
        xy = np.array([[0.64, 0.33], [0.30, 0.60], [0.15, 0.06]])
        prim = np.stack([xy[:, 0] / xy[:, 1], np.ones(3), (1 - xy.sum(1)) / xy[:, 1]])
        self.white_d65 = np.array([0.3127 / 0.3290, 1.0, 0.3583 / 0.3290])
        self.rgb_to_xyz = prim * np.linalg.solve(prim, self.white_d65)

    def sampled(self, values, wavelengths):
        """The piecewise-linear spectra on the 1 nm table (..., 471)."""
        values = np.asarray(values, dtype=np.float64)
        flat = values.reshape(-1, values.shape[-1])
        out = np.stack([np.interp(self.nm, wavelengths, v, left=0.0, right=0.0) for v in flat])
        return out.reshape(values.shape[:-1] + (self.nm.size,))

    def emission_xyz(self, values, wavelengths):
        return (self.sampled(values, wavelengths) * self.tau) @ self.cmf / self.K

    def _lit(self, values, wavelengths):
        return (self.sampled(values, wavelengths) * self.tau * self.d65) @ self.cmf

    def reflectance_xyz(self, values, wavelengths):
        """Under D65, normalised so that rho = 1 on the grid has Y = 1 (docs/DESIGN.md §3)."""
        return self._lit(values, wavelengths) / self._lit(np.ones(len(wavelengths)), wavelengths)[1]

    def xyz_of_rgb(self, rgb):
        return np.asarray(rgb, dtype=np.float64) @ self.rgb_to_xyz.T

    def reflectance_target(self, rgb, wavelengths):
        """White balance by XYZ scaling (docs/DESIGN.md §3): RGB (1, 1, 1) is rho = 1."""
        w_ref = self.reflectance_xyz(np.ones(len(wavelengths)), wavelengths)
        return self.xyz_of_rgb(rgb) * (w_ref / self.white_d65)


@pytest.fixture(scope="session")
def oracle():
    return Oracle()


@pytest.fixture(scope="session")
def sp():
    import spectralize

    return spectralize


def relative_error(xyz, target):
    """Max over colours of |xyz - target| / max|target| (docs/DESIGN.md §3)."""
    scale = np.maximum(np.abs(target).max(axis=-1), 1e-30)
    return float(np.max(np.abs(xyz - target).max(axis=-1) / scale))
