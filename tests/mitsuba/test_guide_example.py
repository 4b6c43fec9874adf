"""The guide's Mitsuba example (docs/examples/mitsuba_scene.py, shown in docs/guide/mitsuba.md)
runs as shown: it spectralizes its inputs with the CLI, renders the three plugins in one scene
and writes the picture. Oracle: the picture read back (its size, lit pixels of several hues)."""
import os
import subprocess
import sys

import numpy as np

from conftest import EXE, SOURCE


def test_the_guide_example_renders(tmp_path):
    out = tmp_path / "example.png"
    env = dict(os.environ, SPECTRALIZE_EXE=EXE)
    p = subprocess.run([sys.executable, str(SOURCE / "docs/examples/mitsuba_scene.py"), str(out),
                        "8"], capture_output=True, text=True, env=env, timeout=600)
    assert p.returncode == 0, p.stderr
    assert p.stdout.strip() == "rendered example.png: 480x320, 8 spp, llvm_ad_spectral"
    import OpenImageIO as oiio
    img = np.asarray(oiio.ImageInput.open(str(out)).read_image(0, 0, 0, 3, "uint8"), dtype=float)
    assert img.shape == (320, 480, 3)
    assert img.mean() > 40  # lit by the sky
    # The chart's hues: some pixels clearly red, green and blue.
    for c in range(3):
        others = [k for k in range(3) if k != c]
        assert np.any(img[..., c] > img[..., others].max(axis=-1) + 60), c
