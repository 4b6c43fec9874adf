"""The plugins in Mitsuba's other spectral variants: scalar_spectral (Python per sample: slow,
but the same colours) and, where a GPU is present, cuda_ad_spectral (skipped with a message
where not). Oracle: the texture's colour, and the LLVM variant's render."""
import numpy as np
import pytest

from conftest import flat_quad, use, write_image


def test_scalar_spectral_renders_the_same_colours(mi, tmp_path):
    rgb = np.array([[[0.7, 0.2, 0.1], [0.1, 0.5, 0.8]]], np.float32)
    path = tmp_path / "two.exr"
    write_image(path, rgb, colorspace="Linear Rec.709 (sRGB)")
    try:
        use(mi, "scalar_spectral")
        got = flat_quad(mi, {"type": "spectralize_rgb", "filename": str(path),
                             "filter_type": "nearest"}, 2, 1, per_texel=1, spp=256,
                        sampler="stratified")
    finally:
        use(mi, "llvm_ad_spectral")
    assert np.all(np.abs(got - rgb) <= 2e-3), (got, rgb)


def test_cuda_spectral_renders_as_llvm_does(mi, tmp_path):
    try:
        mi.set_variant("cuda_ad_spectral")
    except Exception as e:  # no GPU, or no CUDA driver: nothing to test here
        use(mi, "llvm_ad_spectral")
        pytest.skip("cuda_ad_spectral is not available here (%s)" % str(e).splitlines()[0])
    rgb = np.array([[[0.7, 0.2, 0.1], [0.1, 0.5, 0.8]]], np.float32)
    path = tmp_path / "two.exr"
    write_image(path, rgb, colorspace="Linear Rec.709 (sRGB)")
    tex = {"type": "spectralize_rgb", "filename": str(path), "filter_type": "nearest"}
    try:
        use(mi, "cuda_ad_spectral")
        gpu = flat_quad(mi, tex, 2, 1, spp=4096, sampler="stratified")
    finally:
        use(mi, "llvm_ad_spectral")
    cpu = flat_quad(mi, tex, 2, 1, spp=4096, sampler="stratified")
    assert np.all(np.abs(gpu - cpu) <= 1e-4), (gpu, cpu)
    assert np.all(np.abs(gpu - rgb) <= 5e-4), (gpu, rgb)
