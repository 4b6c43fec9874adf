"""spectralize.usd.textures(): every texture file of an OpenUSD stage decided as a TD would.
Stages are written here with pxr (never checked in, never made by the code under test), and
each file's decision is checked against the expectation written in the test: colour spaces
declared on the root and overridden on a material, sourceColorSpace 'raw' and 'sRGB', an
emissive texture, a DomeLight with an HDRI, UDIM tiles, a material in a referenced layer, a
missing asset, a stage that declares nothing."""
import os
import pathlib
import shutil

import pytest

pxr = pytest.importorskip("pxr")
from pxr import Sdf, Usd, UsdLux, UsdShade  # noqa: E402

SOURCE = pathlib.Path(__file__).resolve().parents[2]
IMAGES = SOURCE / "testimages"


@pytest.fixture(scope="module")
def usd():
    import spectralize.usd
    return spectralize.usd


def texture(stage, path, file, source_space=None):
    t = UsdShade.Shader.Define(stage, path)
    t.CreateIdAttr("UsdUVTexture")
    t.CreateInput("file", Sdf.ValueTypeNames.Asset).Set(file)
    if source_space:
        t.CreateInput("sourceColorSpace", Sdf.ValueTypeNames.Token).Set(source_space)
    return t


def feed(surface, name, type_name, tex, output="rgb"):
    surface.CreateInput(name, type_name).ConnectToSource(tex.ConnectableAPI(), output)


def copy(folder, *names):
    for name in names:
        shutil.copy(IMAGES / "colorchecker_srgb8.png", folder / name)


@pytest.fixture
def studio(tmp_path):
    """A stage: lin_ap1_scene on the root, lin_rec2020_scene on one material, a material in a
    referenced layer, a DomeLight, UDIM tiles, a raw normal map and a missing file."""
    copy(tmp_path, "albedo.png", "normal.png", "glow.png", "rough.1001.png", "rough.1002.png",
         "paint.png")
    (tmp_path / "assets").mkdir()
    copy(tmp_path / "assets", "prop.png")
    shutil.copy(IMAGES / "hdri_sunset_256x128.exr", tmp_path / "sky.exr")
    # The referenced layer: a material whose texture path is relative to that layer.
    prop = Usd.Stage.CreateNew(str(tmp_path / "assets" / "prop.usda"))
    UsdShade.Material.Define(prop, "/Prop")
    prop.SetDefaultPrim(prop.GetPrimAtPath("/Prop"))
    surface = UsdShade.Shader.Define(prop, "/Prop/Surface")
    surface.CreateIdAttr("UsdPreviewSurface")
    feed(surface, "diffuseColor", Sdf.ValueTypeNames.Color3f, texture(prop, "/Prop/Tex", "prop.png"))
    prop.Save()

    stage = Usd.Stage.CreateNew(str(tmp_path / "scene.usda"))
    world = stage.DefinePrim("/World", "Xform")
    stage.SetDefaultPrim(world)
    Usd.ColorSpaceAPI.Apply(world).CreateColorSpaceNameAttr("lin_ap1_scene")
    UsdShade.Material.Define(stage, "/World/Mat")
    s = UsdShade.Shader.Define(stage, "/World/Mat/Surface")
    s.CreateIdAttr("UsdPreviewSurface")
    feed(s, "diffuseColor", Sdf.ValueTypeNames.Color3f, texture(stage, "/World/Mat/Albedo", "albedo.png", "sRGB"))
    feed(s, "normal", Sdf.ValueTypeNames.Normal3f, texture(stage, "/World/Mat/Normal", "normal.png", "raw"))
    feed(s, "emissiveColor", Sdf.ValueTypeNames.Color3f, texture(stage, "/World/Mat/Glow", "glow.png"))
    feed(s, "roughness", Sdf.ValueTypeNames.Float, texture(stage, "/World/Mat/Rough", "rough.<UDIM>.png"), "r")
    # A material that declares its own space.
    painted = UsdShade.Material.Define(stage, "/World/Painted")
    Usd.ColorSpaceAPI.Apply(painted.GetPrim()).CreateColorSpaceNameAttr("lin_rec2020_scene")
    p = UsdShade.Shader.Define(stage, "/World/Painted/Surface")
    p.CreateIdAttr("UsdPreviewSurface")
    feed(p, "diffuseColor", Sdf.ValueTypeNames.Color3f, texture(stage, "/World/Painted/Tex", "paint.png"))
    # A texture whose file is missing.
    texture(stage, "/World/Mat/Missing", "nope.png")
    # A DomeLight, and the referenced material.
    UsdLux.DomeLight.Define(stage, "/World/Sky").CreateTextureFileAttr("sky.exr")
    stage.DefinePrim("/World/Prop").GetReferences().AddReference("./assets/prop.usda")
    stage.Save()
    return tmp_path


def by_file(records):
    return {os.path.basename(r.get("input", r["asset"])): r for r in records}


def test_each_texture_is_decided_by_what_the_stage_declares_and_what_it_feeds(usd, studio):
    records = usd.textures(studio / "scene.usda")
    got = {name: (r.get("colorspace"), r.get("mode")) for name, r in by_file(records).items()}
    assert got == {
        "albedo.png": ("srgb_rec709_scene", "reflectance"),  # sourceColorSpace sRGB wins
        "normal.png": ("data", "data"),                      # raw
        "glow.png": ("lin_ap1_scene", "emission"),           # the root's space, an emissive input
        "rough.1001.png": ("lin_ap1_scene", "data"),         # UDIM tiles feeding roughness
        "rough.1002.png": ("lin_ap1_scene", "data"),
        "paint.png": ("lin_rec2020_scene", "reflectance"),   # the material's own space
        "nope.png": ("lin_ap1_scene", None),                 # missing: a failure
        "sky.exr": ("lin_ap1_scene", "emission"),            # a DomeLight's texture
        "prop.png": ("lin_ap1_scene", "reflectance"),        # through the reference
    }
    r = by_file(records)
    # Files resolved where the layer that names them is; each decision says where it came from.
    assert r["prop.png"]["input"] == str(studio / "assets" / "prop.png")
    assert r["rough.1002.png"]["input"] == str(studio / "rough.1002.png")
    assert r["paint.png"]["colorspace_reason"] == \
        "colorSpace:name 'lin_rec2020_scene' of </World/Painted> (UsdColorSpaceAPI)"
    assert r["albedo.png"]["feeds"] == ["</World/Mat/Surface>.inputs:diffuseColor"]
    assert r["albedo.png"]["prim"] == "/World/Mat/Albedo"
    assert "inputs:normal" in r["normal.png"]["feeds"][0]
    assert r["nope.png"]["failure"] == "/World/Mat/Missing.inputs:file: asset 'nope.png' not found"
    assert "input" not in r["nope.png"]


def test_list_lines_carry_the_decisions_ingest_takes(usd, studio):
    lines = [usd.list_line(r, studio) for r in usd.textures(studio / "scene.usda")]
    by = {os.path.basename(line["input"]): line for line in lines}
    assert by["albedo.png"] == {
        "input": "albedo.png", "source": str(studio), "colorspace": "srgb_rec709_scene",
        "mode": "reflectance",
        "origin": {"where": "</World/Mat/Albedo>.inputs:file", "prim": "/World/Mat/Albedo",
                   "attribute": "inputs:file", "asset": "albedo.png",
                   "feeds": ["</World/Mat/Surface>.inputs:diffuseColor"],
                   "colorspace_reason": "</World/Mat/Albedo>.inputs:sourceColorSpace 'sRGB'",
                   "mode_reason": "feeds a surface colour: </World/Mat/Surface>.inputs:diffuseColor"}}
    # Data: the config's data space, for the reason the stage gives.
    assert by["normal.png"]["colorspace"] == "data" and "mode" not in by["normal.png"]
    assert by["normal.png"]["origin"]["colorspace_reason"] == \
        "</World/Mat/Normal>.inputs:sourceColorSpace 'raw'"
    assert by["sky.exr"]["mode"] == "emission"
    # Inside the stage's folder: relative, so the output mirrors its place (assets/prop.exr).
    assert by["prop.png"]["input"] == os.path.join("assets", "prop.png")
    # The missing file has a line too: ingest fails it, naming its prim.
    assert by["nope.png"]["input"] == "nope.png"
    assert by["nope.png"]["origin"]["where"] == "</World/Mat/Missing>.inputs:file"
    # Without a source folder: the file's path as resolved.
    assert usd.list_line(usd.textures(studio / "scene.usda")[0])["input"] == \
        str(studio / "albedo.png")


def test_a_stage_that_declares_nothing_leaves_the_files_to_decide(usd, tmp_path):
    copy(tmp_path, "a.png")
    stage = Usd.Stage.CreateNew(str(tmp_path / "plain.usda"))
    UsdShade.Material.Define(stage, "/M")
    s = UsdShade.Shader.Define(stage, "/M/S")
    s.CreateIdAttr("UsdPreviewSurface")
    feed(s, "diffuseColor", Sdf.ValueTypeNames.Color3f, texture(stage, "/M/T", "a.png"))
    stage.Save()
    [r] = usd.textures(tmp_path / "plain.usda")
    assert r["colorspace"] is None and r["mode"] == "reflectance"
    line = usd.list_line(r)
    assert (line["input"], line["mode"], "colorspace" in line) == \
        (str(tmp_path / "a.png"), "reflectance", False)
    assert "colorspace_reason" not in line["origin"]


def test_a_stage_that_cannot_be_opened_is_named(usd, tmp_path):
    with pytest.raises(OSError, match="missing.usda"):
        usd.textures(tmp_path / "missing.usda")
    (tmp_path / "broken.usda").write_text("#usda 1.0\n( this is not usd\n")
    with pytest.raises(OSError, match="broken.usda"):
        usd.textures(tmp_path / "broken.usda")


def manifest(folder):
    import json
    return {os.path.basename(r["input"]): r
            for r in map(json.loads, (folder / "spectralize-ingest.jsonl").read_text().splitlines())
            if "input" in r}


def test_a_stage_is_ingested_with_its_decisions(usd, studio, tmp_path_factory):
    """Each file converted as the stage decides it (interop IDs resolved to the config's
    spaces: lin_ap1_scene is the shipped config's ACEScg), data skipped, a rerun converts
    nothing; the missing asset is named with its prim."""
    out = tmp_path_factory.mktemp("out")
    summary = usd.ingest(studio / "scene.usda", out, wavelengths="400:700:20")
    m = manifest(out)
    assert (m["albedo.png"]["colorspace"], m["albedo.png"]["mode"]) == ("sRGB - Texture", "reflectance")
    assert (m["glow.png"]["colorspace"], m["glow.png"]["mode"]) == ("ACEScg", "emission")
    assert (m["paint.png"]["colorspace"], m["paint.png"]["mode"]) == ("Linear Rec.2020", "reflectance")
    assert (m["sky.exr"]["colorspace"], m["sky.exr"]["mode"]) == ("ACEScg", "emission")
    assert m["prop.png"]["status"] == "converted"
    for data in ("normal.png", "rough.1001.png", "rough.1002.png"):
        assert m[data]["status"] == "skipped_data", m[data]
    assert [r["prim"] for r in summary["asset_failures"]] == ["/World/Mat/Missing"]
    again = usd.ingest(studio / "scene.usda", out, wavelengths="400:700:20")
    assert again["converted"] == 0 and again["up_to_date"] == summary["converted"]


def test_the_override_layer_composes_over_the_stage_and_names_the_spectra(usd, studio, tmp_path_factory):
    """spectral.usda opens in pxr, has the stage as its sublayer, adds only spectralize:
    attributes (the original's own untouched), names files that exist; the lights' spectra
    are there and in lights/; the original layers are not written."""
    import json
    before = {p: p.stat().st_mtime_ns for p in studio.rglob("*.usda")}
    out = tmp_path_factory.mktemp("out")
    summary = usd.ingest(studio / "scene.usda", out, wavelengths="400:700:20")
    assert {p: p.stat().st_mtime_ns for p in studio.rglob("*.usda")} == before
    stage = Usd.Stage.Open(str(out / "spectral.usda"))
    layer = stage.GetRootLayer()
    assert [os.path.normpath(os.path.join(out, p)) for p in layer.subLayerPaths] == \
        [str(studio / "scene.usda")]
    albedo = stage.GetPrimAtPath("/World/Mat/Albedo")
    spectral = albedo.GetAttribute("spectralize:file").Get()
    assert os.path.isfile(spectral.resolvedPath) and spectral.resolvedPath.endswith("albedo.exr")
    assert albedo.GetAttribute("spectralize:mode").Get() == "reflectance"
    # The original's inputs compose unchanged; data maps get no spectral file.
    assert UsdShade.Shader(albedo).GetInput("file").Get().path == "albedo.png"
    assert not stage.GetPrimAtPath("/World/Mat/Normal").GetAttribute("spectralize:file")
    # Through the reference too.
    prop = stage.GetPrimAtPath("/World/Prop/Tex").GetAttribute("spectralize:file").Get()
    assert os.path.isfile(prop.resolvedPath)
    # Only spectralize: attributes are authored by the layer.
    for spec in layer.rootPrims:
        for prim in [spec] + list(spec.nameChildren):
            def walk(p):
                for a in p.attributes:
                    assert a.name.startswith("spectralize:"), a.name
                for c in p.nameChildren:
                    walk(c)
            walk(prim)
    # The DomeLight's spectrum: the same in the layer and in its JSON file.
    sky = stage.GetPrimAtPath("/World/Sky")
    values = list(sky.GetAttribute("spectralize:values").Get())
    assert len(values) == len(sky.GetAttribute("spectralize:wavelengths").Get()) == 16
    [light] = [r for r in summary["lights"] if r["prim"] == "/World/Sky"]
    assert json.loads(pathlib.Path(light["file"]).read_text())["values"] == pytest.approx(values)
    assert not list(out.rglob("*.spectralize-*.tmp"))  # no temporaries left


def test_a_materialx_network_is_walked_as_a_preview_surface_is(usd, tmp_path):
    # MaterialX nodes as USD shaders (what Houdini, Maya and Omniverse write): standard_surface
    # fed by image nodes. The file input's colorSpace metadata (MaterialX's colorspace) is the
    # space; base_color is a surface colour, emission_color light; a normal map through
    # ND_normalmap and a coat normal are data; a tiled image of roughness is data too.
    copy(tmp_path, "base.png", "glow.png", "nrm.png", "coat.png", "rough.png")
    stage = Usd.Stage.CreateNew(str(tmp_path / "mtlx.usda"))
    Usd.ColorSpaceAPI.Apply(stage.DefinePrim("/World")).CreateColorSpaceNameAttr("lin_ap1_scene")
    material = UsdShade.Material.Define(stage, "/World/Mat")
    surface = UsdShade.Shader.Define(stage, "/World/Mat/Surface")
    surface.CreateIdAttr("ND_standard_surface_surfaceshader")
    material.CreateSurfaceOutput("mtlx").ConnectToSource(
        surface.CreateOutput("out", Sdf.ValueTypeNames.Token))

    def image(name, file, kind, node="ND_image_color3", space=None):
        t = UsdShade.Shader.Define(stage, "/World/Mat/" + name)
        t.CreateIdAttr(node)
        f = t.CreateInput("file", Sdf.ValueTypeNames.Asset)
        f.Set(file)
        if space:
            f.GetAttr().SetColorSpace(space)
        t.CreateOutput("out", kind)
        return t

    c3, v3, fl = Sdf.ValueTypeNames.Color3f, Sdf.ValueTypeNames.Float3, Sdf.ValueTypeNames.Float
    feed(surface, "base_color", c3, image("Base", "base.png", c3, space="srgb_texture"), "out")
    feed(surface, "emission_color", c3, image("Glow", "glow.png", c3), "out")
    normalmap = UsdShade.Shader.Define(stage, "/World/Mat/NormalMap")
    normalmap.CreateIdAttr("ND_normalmap")
    feed(normalmap, "in", v3, image("Nrm", "nrm.png", v3, "ND_image_vector3"), "out")
    normalmap.CreateOutput("out", v3)
    feed(surface, "normal", v3, normalmap, "out")
    feed(surface, "coat_normal", v3, image("Coat", "coat.png", v3, "ND_image_vector3"), "out")
    feed(surface, "specular_roughness", fl,
         image("Rough", "rough.png", fl, "ND_tiledimage_float"), "out")
    stage.Save()
    r = by_file(usd.textures(tmp_path / "mtlx.usda"))
    got = {name: (r[name].get("colorspace"), r[name].get("mode")) for name in r}
    assert got == {
        "base.png": ("srgb_texture", "reflectance"),   # the file input's colorSpace
        "glow.png": ("lin_ap1_scene", "emission"),     # the root's space, an emissive input
        "nrm.png": ("lin_ap1_scene", "data"),          # through ND_normalmap to normal
        "coat.png": ("lin_ap1_scene", "data"),         # a surface shader's non-colour input
        "rough.png": ("lin_ap1_scene", "data"),
    }
    assert r["base.png"]["colorspace_reason"] == "colorSpace 'srgb_texture' of </World/Mat/Base>.inputs:file"
    assert r["nrm.png"]["feeds"] == ["</World/Mat/Surface>.inputs:normal"]
    assert r["coat.png"]["mode_reason"] == "feeds no colour: </World/Mat/Surface>.inputs:coat_normal"


def test_a_rect_lights_picture_is_light(usd, tmp_path):
    # A RectLight with a texture (a screen, a softbox's print) emits it: emission, in the space
    # the stage declares at the light.
    copy(tmp_path, "screen.png")
    stage = Usd.Stage.CreateNew(str(tmp_path / "r.usda"))
    Usd.ColorSpaceAPI.Apply(stage.DefinePrim("/World")).CreateColorSpaceNameAttr("lin_rec709_scene")
    UsdLux.RectLight.Define(stage, "/World/Screen").CreateTextureFileAttr("screen.png")
    stage.Save()
    (r,) = usd.textures(tmp_path / "r.usda")
    assert (r["colorspace"], r["mode"]) == ("lin_rec709_scene", "emission")
    assert r["attribute"] == "inputs:texture:file"
    assert r["mode_reason"] == "the texture of RectLight </World/Screen>"
