"""The files round-trip: spectral_bitmap on spectralize's OpenEXR of a texture renders what
spectralize_rgb renders from the texture (the same model and conventions), and spectral_envmap
on spectralize's OpenEXR of an HDRI, lighting a white diffuse sphere, renders what Mitsuba
renders from the RGB map (its RGB variant: RGB transport, exact for the map's own colours) to
the noise floor; Mitsuba's spectral envmap (its sigmoid uplift) is measured beside it.
Oracles: the renders of the other path, and two seeds for the noise."""
import subprocess

import numpy as np
import pytest

from conftest import EXE, IMAGES, flat_quad, rms, use, write_image

H, W = 6, 8
MITSUBA_GRID = ["--wavelengths", "360:830:5", "--observer", "cie1931_mitsuba", "--format", "float"]


def spectralize(*args):
    p = subprocess.run([EXE, *map(str, args), "-q"], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr


def test_a_texture_through_its_spectral_file_renders_as_through_the_table(mi, tmp_path):
    rng = np.random.default_rng(11)
    rgb = rng.uniform(0.03, 0.92, (H, W, 3)).astype(np.float32)
    src = tmp_path / "albedo.exr"
    write_image(src, rgb, colorspace="Linear Rec.709 (sRGB)")
    spectral = tmp_path / "albedo_spectral.exr"
    spectralize(src, "-o", spectral, "--mode", "reflectance", *MITSUBA_GRID)
    table = {"type": "spectralize_rgb", "filename": str(src), "filter_type": "nearest"}
    bands = {"type": "spectral_bitmap", "filename": str(spectral), "filter_type": "nearest"}
    a1, a2 = (flat_quad(mi, table, W, H, spp=4096, sampler="stratified", seed=s) for s in (1, 2))
    b1 = flat_quad(mi, bands, W, H, spp=4096, sampler="stratified", seed=1)
    floor = rms(a1 - a2) / np.sqrt(2)
    print("spectral_bitmap vs spectralize_rgb: %.2e (noise floor %.2e)" % (rms(b1 - a1), floor))
    # The file holds the exact solver's spectra, the table its blends: both reproduce the
    # texel (1e-5 relative), so the renders agree far below any render's noise.
    assert rms(b1 - a1) <= 3e-5 + 2 * floor
    assert rms(b1 - rgb) <= 2e-4


def test_an_hdri_through_its_spectral_file_lights_as_the_rgb_map(tmp_path):
    mitsuba = pytest.importorskip("mitsuba")
    hdri = IMAGES / "hdri_sunset_256x128.exr"
    spectral = tmp_path / "sunset_spectral.exr"
    spectralize(hdri, "-o", spectral, "--mode", "emission", *MITSUBA_GRID)

    def sphere(em, spp, seed):
        scene = mitsuba.load_dict({
            "type": "scene", "integrator": {"type": "path", "max_depth": 2},
            "sensor": {"type": "perspective", "fov": 30,
                       "to_world": mitsuba.ScalarTransform4f().look_at(
                           origin=[0, 0, 5], target=[0, 0, 0], up=[0, 1, 0]),
                       "film": {"type": "hdrfilm", "width": 24, "height": 24,
                                "rfilter": {"type": "box"}, "pixel_format": "rgb"},
                       "sampler": {"type": "independent", "sample_count": spp}},
            "sphere": {"type": "sphere",
                       "bsdf": {"type": "diffuse", "reflectance": {"type": "uniform", "value": 1.0}}},
            "light": em})
        img = np.array(mitsuba.render(scene, seed=seed), dtype=np.float64)
        return img

    rgb_map = {"type": "envmap", "filename": str(hdri)}
    use(mitsuba, "llvm_ad_rgb")
    references = [sphere(rgb_map, 2048, seed) for seed in range(100, 104)]
    use(mitsuba, "llvm_ad_spectral")
    ours = [sphere({"type": "spectral_envmap", "filename": str(spectral)}, 1024, seed)
            for seed in range(1, 7)]
    stock = [sphere(rgb_map, 1024, seed) for seed in range(1, 7)]
    lit = references[0].sum(-1) > 0.05
    # The mean over the lit pixels of each render; the noise of those means from the spread of
    # the seeds (a bright sun makes neighbouring pixels' noise add up: not per-pixel noise).
    means = lambda imgs: np.array([img[lit].mean(axis=0) for img in imgs])
    ref, mine, theirs = means(references), means(ours), means(stock)
    stderr = lambda m: m.std(axis=0, ddof=1) / np.sqrt(len(m))
    floor = np.sqrt(stderr(ref) ** 2 + stderr(mine) ** 2)
    err_ours = np.abs(mine.mean(0) - ref.mean(0))
    err_stock = np.abs(theirs.mean(0) - ref.mean(0))
    print("white sphere, mean over %d pixels: RGB variant %s; spectral_envmap off by %s (noise "
          "floor %s); Mitsuba's spectral envmap off by %s" % (
              lit.sum(), np.round(ref.mean(0), 4), np.round(err_ours, 5), np.round(floor, 5),
              np.round(err_stock, 5)))
    assert np.all(err_ours <= 4 * floor + 3e-4 * ref.mean(0)), (err_ours, floor)


def test_the_environment_maps_sampling_is_consistent(mi, tmp_path):
    """Its directions are drawn with the density pdf_direction() reports, that density
    integrates to 1 over the sphere, and a sample's weight is the radiance over the density.
    Oracles: the definitions (uniform directions for the integral, 200,000 of them)."""
    import drjit as dr
    spectral = tmp_path / "sunset_spectral.exr"
    spectralize(IMAGES / "hdri_sunset_256x128.exr", "-o", spectral, "--mode", "emission",
                *MITSUBA_GRID)
    em = mi.load_dict({"type": "spectral_envmap", "filename": str(spectral),
                       "to_world": mi.ScalarTransform4f().rotate([0, 1, 0], 30)})
    n = 200_000
    rng = np.random.default_rng(2)
    it = dr.zeros(mi.Interaction3f, n)
    it.wavelengths = mi.Spectrum(*[mi.Float(rng.uniform(400, 700, n).astype(np.float32))
                                   for _ in range(4)])
    ds, weight = em.sample_direction(it, mi.Point2f(rng.random(n), rng.random(n)))
    pdf = em.pdf_direction(it, ds)
    ok = np.array(ds.pdf) > 1e-3
    assert np.allclose(np.array(pdf)[ok], np.array(ds.pdf)[ok], rtol=2e-3)
    si = dr.zeros(mi.SurfaceInteraction3f, n)
    si.wi = -ds.d
    si.wavelengths = it.wavelengths
    radiance = np.array(em.eval(si))
    assert np.allclose(np.array(weight)[:, ok] * np.array(ds.pdf)[ok], radiance[:, ok],
                       rtol=2e-3, atol=1e-6)
    # The density integrates to 1: uniform directions, pdf / (1 / 4 pi), averaged.
    u = mi.warp.square_to_uniform_sphere(mi.Point2f(rng.random(n), rng.random(n)))
    probe = dr.zeros(mi.DirectionSample3f, n)
    probe.d = u
    integral = float(np.mean(np.array(em.pdf_direction(it, probe))) * 4 * np.pi)
    assert abs(integral - 1) < 0.02, integral
