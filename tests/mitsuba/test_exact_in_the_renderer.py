"""spectralize_rgb in Mitsuba 3 renders a texture's own colours: a flat quad lit by Mitsuba's
d65 environment renders each texel's linear Rec.709 RGB to the render's noise floor (measured by
two seeds), and, with stratified samples that remove the noise, closer than Mitsuba's own
bitmap (its sigmoid uplift). Oracle: the texture's pixels, written by the test."""
import numpy as np

from conftest import flat_quad, rms, write_image

H, W = 6, 8


def texture(tmp_path):
    rng = np.random.default_rng(7)
    rgb = rng.uniform(0.03, 0.92, (H, W, 3)).astype(np.float32)
    rgb[0, :4] = [[0.8, 0.05, 0.05], [0.05, 0.7, 0.05], [0.05, 0.05, 0.8], [1.0, 1.0, 1.0]]
    path = tmp_path / "albedo.exr"
    write_image(path, rgb, colorspace="Linear Rec.709 (sRGB)")
    return path, rgb.astype(np.float64)


def test_a_texture_renders_its_own_colours(mi, tmp_path):
    path, rgb = texture(tmp_path)
    ours = {"type": "spectralize_rgb", "filename": str(path), "filter_type": "nearest"}
    stock = {"type": "bitmap", "filename": str(path), "filter_type": "nearest"}
    # Independent samples: the noise floor from two seeds, and the error within it.
    a1, a2 = (flat_quad(mi, ours, W, H, spp=2048, seed=s) for s in (1, 2))
    b1, b2 = (flat_quad(mi, stock, W, H, spp=2048, seed=s) for s in (1, 2))
    floor = rms(a1 - a2) / np.sqrt(2)
    err_ours, err_stock = rms(a1 - rgb), rms(b1 - rgb)
    print("independent 2048 spp: noise floor %.2e, error spectralize_rgb %.2e, bitmap %.2e"
          % (floor, err_ours, err_stock))
    assert err_ours <= 1.3 * floor, (err_ours, floor)
    # Stratified samples: the noise (~1e-6) below both uplifts' errors.
    s1, s2 = (flat_quad(mi, ours, W, H, spp=4096, sampler="stratified", seed=s) for s in (1, 2))
    t1 = flat_quad(mi, stock, W, H, spp=4096, sampler="stratified", seed=1)
    floor = rms(s1 - s2) / np.sqrt(2)
    # What Mitsuba makes of a flat unit reflectance under its d65 (its D65 table and film
    # matrix): the part of every texel's error no spectrum of that colour can remove.
    white = flat_quad(mi, {"type": "uniform", "value": 1.0}, 1, 1, spp=8192,
                      sampler="stratified")[0, 0]
    err_ours, err_stock = rms(s1 - rgb), rms(t1 - rgb)
    print("stratified 4096 spp: noise floor %.2e, Mitsuba's white %s, error spectralize_rgb "
          "%.2e, bitmap %.2e" % (floor, np.round(white - 1, 6), err_ours, err_stock))
    assert floor < 1e-5
    assert err_ours < err_stock
    assert err_ours <= 2e-4 + rms(rgb * (white - 1))
    # Within [0, 1]: no texel brighter than the white reflector.
    assert np.all(s1 <= white * (1 + 1e-5))


def test_filtering_blends_spectra_whose_colour_is_the_filtered_colour(mi, tmp_path):
    """Bilinear: the quad rendered at 4x the texture's resolution shows, between texel centres,
    the bilinear blend of the texels' RGB (as Mitsuba's bitmap filters), to the noise floor."""
    path, rgb = texture(tmp_path)
    k = 4
    tex = {"type": "spectralize_rgb", "filename": str(path), "wrap_mode": "clamp"}
    img1, img2 = (flat_quad(mi, tex, W * k, H * k, per_texel=1, spp=2048, sampler="stratified",
                            seed=s) for s in (1, 2))
    # The oracle: bilinear interpolation of the texels at the pixel centres, clamped at edges.
    ys = (np.arange(H * k) + 0.5) / k - 0.5
    xs = (np.arange(W * k) + 0.5) / k - 0.5
    y0, x0 = np.floor(ys).astype(int), np.floor(xs).astype(int)
    fy, fx = (ys - y0)[:, None, None], (xs - x0)[None, :, None]
    cy = lambda i: np.clip(i, 0, H - 1)
    cx = lambda i: np.clip(i, 0, W - 1)
    want = ((1 - fy) * (1 - fx) * rgb[cy(y0)][:, cx(x0)] + (1 - fy) * fx * rgb[cy(y0)][:, cx(x0 + 1)]
            + fy * (1 - fx) * rgb[cy(y0 + 1)][:, cx(x0)] + fy * fx * rgb[cy(y0 + 1)][:, cx(x0 + 1)])
    floor = rms(img1 - img2) / np.sqrt(2)
    assert rms(img1 - want) <= 2e-4 + 1.3 * floor, (rms(img1 - want), floor)


def test_a_light_renders_its_colour(mi):
    """mode='emission': an area light of a colour, seen directly, renders that colour (any
    brightness), as Mitsuba's film integrates (observer cie1931_mitsuba)."""
    for colour in ([1.0, 0.5, 0.2], [30.0, 20.0, 5.0], [0.05, 0.2, 0.9]):
        scene = mi.load_dict({
            "type": "scene", "integrator": {"type": "direct"},
            "sensor": {"type": "orthographic",
                       "to_world": mi.ScalarTransform4f().look_at(origin=[0, 0, 1],
                                                                  target=[0, 0, 0], up=[0, 1, 0]),
                       "film": {"type": "hdrfilm", "width": 2, "height": 2,
                                "rfilter": {"type": "box"}, "pixel_format": "rgb"},
                       "sampler": {"type": "stratified", "sample_count": 4096}},
            "quad": {"type": "rectangle", "emitter": {"type": "area", "radiance": {
                         "type": "spectralize_rgb", "color": colour, "mode": "emission"}}}})
        got = np.array(mi.render(scene), dtype=np.float64).reshape(-1, 3).mean(0)
        assert np.all(np.abs(got - colour) <= 5e-4 * max(colour)), (colour, got)
