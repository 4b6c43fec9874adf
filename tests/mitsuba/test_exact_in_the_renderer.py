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


def test_wrap_modes_and_to_uv_address_texels_as_the_bitmap_does(mi, tmp_path):
    """The same uv transform and wrap mode on Mitsuba's bitmap and on spectralize_rgb show the
    same texels (their colours differ by bitmap's uplift error, < 5e-4, not by a texel). The map
    (u, v) -> (2u + 1/4, 2v - 1/2) puts each pixel of a 2x render on one whole texel, two texels
    and three rows off, wrapped beyond the texture's edges: no pixel straddles two texels."""
    path, rgb = texture(tmp_path)
    to_uv = mi.ScalarTransform3f().translate([0.25, -0.5]) @ mi.ScalarTransform3f().scale([2, 2])
    for wrap in ("repeat", "mirror", "clamp"):
        for filt in ("nearest", "bilinear"):
            common = {"filename": str(path), "filter_type": filt, "wrap_mode": wrap,
                      "to_uv": to_uv}
            ours, again = (flat_quad(mi, dict(common, type="spectralize_rgb"), W * 2, H * 2,
                                     per_texel=1, spp=1024, sampler="stratified", seed=s)
                           for s in (1, 2))
            stock = flat_quad(mi, dict(common, type="bitmap"), W * 2, H * 2, per_texel=1,
                              spp=1024, sampler="stratified")
            # A texel missed is a difference of ~0.1 in a pixel; noise and uplift ~1e-3.
            noise = rms(ours - again) / np.sqrt(2)
            assert np.max(np.abs(ours - stock)) <= 0.02, (wrap, filt)
            assert rms(ours - stock) <= 5e-4 + 2 * noise, (wrap, filt, rms(ours - stock), noise)


def test_scalar_and_rgb_lookups_are_the_bitmaps(mi, tmp_path):
    """eval_3, eval_1 and mean() answer as Mitsuba's bitmap (raw) does for the same linear
    Rec.709 texture, so BSDF parameters taken from a texture (a roughness) render the same."""
    import drjit as dr
    path, rgb = texture(tmp_path)
    common = {"filename": str(path), "filter_type": "bilinear"}
    ours = mi.load_dict(dict(common, type="spectralize_rgb"))
    stock = mi.load_dict(dict(common, type="bitmap", raw=True))
    rng = np.random.default_rng(3)
    si = dr.zeros(mi.SurfaceInteraction3f, 1000)
    si.uv = mi.Point2f(rng.random(1000), rng.random(1000))
    assert np.allclose(np.array(ours.eval_3(si)), np.array(stock.eval_3(si)), atol=1e-6)
    assert np.allclose(np.array(ours.eval_1(si)), np.array(stock.eval_1(si)), atol=1e-5)
    assert abs(ours.mean() - stock.mean()) <= 1e-5
    # A principled BSDF whose roughness is the texture's luminance.
    def render(tex):
        return flat_quad(mi, None, W, H, spp=1024, sampler="stratified", bsdf={
            "type": "principled", "base_color": {"type": "uniform", "value": 0.5},
            "roughness": tex, "specular": 0.8})
    assert rms(render(dict(common, type="spectralize_rgb"))
               - render(dict(common, type="bitmap", raw=True))) <= 1e-5


def primaries_to_xyz(xy, white):
    """RGB -> XYZ of primaries and a white (CIE xy), the white at Y = 1."""
    xy = np.asarray(xy, dtype=np.float64)
    p = np.stack([xy[:, 0] / xy[:, 1], np.ones(3), (1 - xy.sum(1)) / xy[:, 1]])
    w = np.array([white[0] / white[1], 1.0, (1 - white[0] - white[1]) / white[1]])
    return p * np.linalg.solve(p, w)


def bradford(src_white, dst_white):
    b = np.array([[0.8951, 0.2664, -0.1614], [-0.7502, 1.7135, 0.0367],
                  [0.0389, -0.0685, 1.0296]])
    xyz = lambda w: np.array([w[0] / w[1], 1.0, (1 - w[0] - w[1]) / w[1]])
    return np.linalg.inv(b) @ np.diag((b @ xyz(dst_white)) / (b @ xyz(src_white))) @ b


def test_a_texture_in_another_colour_space_renders_its_colours(mi, tmp_path):
    """ACEScg (told by its EXR chromaticities, as the CLI decides it): colours of the Rec.709
    reflectance gamut written in ACEScg render as those Rec.709 colours. Oracle: the AP1
    primaries and the ACES white (ACES TB-2014-004), Bradford-adapted to D65 as the config's
    ACEScg is, and the IEC Rec.709 matrix."""
    import OpenImageIO as oiio
    rng = np.random.default_rng(13)
    rec709 = rng.uniform(0.05, 0.9, (H, W, 3))
    d65, aces = (0.3127, 0.3290), (0.32168, 0.33767)
    ap1_to_xyz = bradford(aces, d65) @ primaries_to_xyz(
        [[0.713, 0.293], [0.165, 0.830], [0.128, 0.044]], aces)
    acescg = rec709 @ (np.linalg.inv(ap1_to_xyz) @ primaries_to_xyz(
        [[0.64, 0.33], [0.30, 0.60], [0.15, 0.06]], d65)).T
    path = tmp_path / "plate_ap1.exr"
    spec = oiio.ImageSpec(W, H, 3, "float")
    spec.attribute("chromaticities", oiio.TypeDesc("float[8]"),
                   (0.713, 0.293, 0.165, 0.830, 0.128, 0.044, 0.32168, 0.33767))
    out = oiio.ImageOutput.create(str(path))
    assert out.open(str(path), spec)
    assert out.write_image(np.ascontiguousarray(acescg, dtype=np.float32))
    out.close()
    ours = {"type": "spectralize_rgb", "filename": str(path), "filter_type": "nearest",
            "mode": "reflectance"}
    got = flat_quad(mi, ours, W, H, spp=4096, sampler="stratified")
    assert rms(got - rec709) <= 5e-4, rms(got - rec709)
