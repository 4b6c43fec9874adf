"""A USD stage ingested, from Python (spectralize.usd.ingest) and from the command line
(`spectralize ingest STAGE.usda`): the manifest names the prim and input behind each decision
and the reasons the stage gives; a file whose own tag contradicts the stage is reported and
the stage followed; textures inside a .usdz; a changed layer reconverts only what it changes;
failures (a missing asset, a layer that cannot be composed, a light that cannot be made, no
OpenUSD in the Python) named with the exit status ingest's rules give. Stages are written
here with pxr; expectations are written in the test."""
import fcntl
import json
import os
import pathlib
import shutil
import subprocess
import sys

import pytest

pytest.importorskip("pxr")
from pxr import Gf, Sdf, Usd, UsdLux, UsdShade, UsdUtils  # noqa: E402

SOURCE = pathlib.Path(__file__).resolve().parents[2]
IMAGES = SOURCE / "testimages"
EXE = os.environ.get("SPECTRALIZE_EXE")
GRID = "400:700:20"


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


def surface(stage, material, feeds):
    """A UsdPreviewSurface of `material` fed by {input: (texture prim, file, sourceColorSpace)}."""
    UsdShade.Material.Define(stage, material)
    s = UsdShade.Shader.Define(stage, material + "/Surface")
    s.CreateIdAttr("UsdPreviewSurface")
    for name, (prim, file, space) in feeds.items():
        kind = Sdf.ValueTypeNames.Normal3f if name == "normal" else Sdf.ValueTypeNames.Color3f
        s.CreateInput(name, kind).ConnectToSource(
            texture(stage, prim, file, space).ConnectableAPI(), "rgb")


def tagged_exr(src, dst, interop_id):
    """A copy of `src` whose header says it is `interop_id` (colorInteropID), by oiiotool."""
    subprocess.run(["oiiotool", str(src), "--attrib", "colorInteropID", interop_id, "-o",
                    str(dst)], check=True)


@pytest.fixture
def shop(tmp_path):
    """A stage: an sRGB albedo, a raw normal map, an emissive map in the root's ACEScg, a
    material in Rec.2020, one light."""
    folder = tmp_path / "shop"
    (folder / "tex").mkdir(parents=True)
    for name in ("albedo.png", "normal.png", "glow.png", "paint.png"):
        shutil.copy(IMAGES / "colorchecker_srgb8.png", folder / "tex" / name)
    stage = Usd.Stage.CreateNew(str(folder / "shop.usda"))
    world = stage.DefinePrim("/World", "Xform")
    Usd.ColorSpaceAPI.Apply(world).CreateColorSpaceNameAttr("lin_ap1_scene")
    surface(stage, "/World/Mat", {"diffuseColor": ("/World/Mat/Albedo", "tex/albedo.png", "sRGB"),
                                  "normal": ("/World/Mat/Normal", "tex/normal.png", "raw"),
                                  "emissiveColor": ("/World/Mat/Glow", "tex/glow.png", None)})
    painted = stage.DefinePrim("/World/Painted", "Material")
    Usd.ColorSpaceAPI.Apply(painted).CreateColorSpaceNameAttr("lin_rec2020_scene")
    surface(stage, "/World/Painted", {"diffuseColor": ("/World/Painted/Tex", "tex/paint.png", None)})
    UsdLux.SphereLight.Define(stage, "/World/Key").CreateColorAttr(Gf.Vec3f(1.0, 0.8, 0.6))
    stage.Save()
    return folder


def manifest(out):
    return {os.path.basename(r["input"]): r
            for r in map(json.loads, (out / "spectralize-ingest.jsonl").read_text().splitlines())
            if "input" in r}


def test_the_manifest_names_the_prim_and_input_behind_each_decision(usd, shop, tmp_path):
    out = tmp_path / "out"
    usd.ingest(shop / "shop.usda", out, wavelengths=GRID)
    m = manifest(out)
    albedo = m["albedo.png"]
    assert albedo["status"] == "converted"
    assert albedo["origin"]["where"] == "</World/Mat/Albedo>.inputs:file"
    assert albedo["origin"]["feeds"] == ["</World/Mat/Surface>.inputs:diffuseColor"]
    # The reasons are the stage's, not "--colorspace" / "--mode".
    assert albedo["colorspace_reason"] == "</World/Mat/Albedo>.inputs:sourceColorSpace 'sRGB'"
    assert albedo["mode_reason"] == "feeds a surface colour: </World/Mat/Surface>.inputs:diffuseColor"
    assert m["paint.png"]["colorspace_reason"] == \
        "colorSpace:name 'lin_rec2020_scene' of </World/Painted> (UsdColorSpaceAPI)"
    assert m["normal.png"]["status"] == "skipped_data"
    assert "sourceColorSpace 'raw'" in m["normal.png"]["reason"]
    # The output mirrors the file's place under the stage's folder.
    assert pathlib.Path(albedo["output"]) == out / "tex" / "albedo.exr"
    # A rerun: up to date, the reasons read back from the outputs' headers.
    usd.ingest(shop / "shop.usda", out, wavelengths=GRID)
    again = manifest(out)["albedo.png"]
    assert again["status"] == "up_to_date"
    assert again["colorspace_reason"] == albedo["colorspace_reason"]
    assert again["origin"] == albedo["origin"]


def test_a_file_whose_own_tag_contradicts_the_stage_is_reported_and_the_stage_wins(usd, tmp_path):
    folder = tmp_path / "stage"
    folder.mkdir()
    tagged_exr(IMAGES / "hdri_sunset_256x128.exr", folder / "photo.exr", "srgb_rec709_scene")
    tagged_exr(IMAGES / "hdri_sunset_256x128.exr", folder / "glow.exr", "srgb_rec709_scene")
    stage = Usd.Stage.CreateNew(str(folder / "s.usda"))
    surface(stage, "/M", {"normal": ("/M/Photo", "photo.exr", "raw"),
                          "emissiveColor": ("/M/Glow", "glow.exr", None)})
    Usd.ColorSpaceAPI.Apply(stage.GetPrimAtPath("/M")).CreateColorSpaceNameAttr("lin_ap1_scene")
    stage.Save()
    out = tmp_path / "out"
    usd.ingest(folder / "s.usda", out, wavelengths=GRID)
    m = manifest(out)
    photo, glow = m["photo.exr"], m["glow.exr"]
    assert photo["status"] == "skipped_data"  # the stage says raw: followed
    assert "colorInteropID 'srgb_rec709_scene'" in photo["contradiction"]
    assert "sourceColorSpace 'raw'" in photo["contradiction"]
    assert (glow["status"], glow["colorspace"]) == ("converted", "ACEScg")
    assert "colorInteropID 'srgb_rec709_scene'" in glow["contradiction"]
    assert "'ACEScg' is followed" in glow["contradiction"]
    assert any("'ACEScg' is followed" in w for w in glow["warnings"])
    # Where the stage agrees with the file, nothing is said.
    assert "contradiction" not in manifest(out).get("albedo.png", {})


def test_textures_inside_a_usdz_are_converted_and_found_up_to_date(usd, tmp_path):
    folder = tmp_path / "asset"
    (folder / "tex").mkdir(parents=True)
    shutil.copy(IMAGES / "colorchecker_srgb8.png", folder / "tex" / "albedo.png")
    stage = Usd.Stage.CreateNew(str(folder / "asset.usda"))
    surface(stage, "/Asset", {"diffuseColor": ("/Asset/Albedo", "tex/albedo.png", "sRGB")})
    stage.SetDefaultPrim(stage.GetPrimAtPath("/Asset"))
    stage.Save()
    package = tmp_path / "asset.usdz"
    assert UsdUtils.CreateNewUsdzPackage(str(folder / "asset.usda"), str(package))
    shutil.rmtree(folder)  # only the package is left
    out = tmp_path / "out"
    summary = usd.ingest(package, out, wavelengths=GRID)
    [record] = summary["textures"]
    assert record["packaged"].startswith(str(package) + "[")
    m = manifest(out)["albedo.png"]
    assert (m["status"], m["mode"], m["colorspace"]) == ("converted", "reflectance", "sRGB - Texture")
    assert m["origin"]["packaged"] == record["packaged"]
    # The layer over the package names the spectral file.
    layer = Usd.Stage.Open(str(out / "spectral.usda"))
    spectral = layer.GetPrimAtPath("/Asset/Albedo").GetAttribute("spectralize:file").Get()
    assert os.path.isfile(spectral.resolvedPath)
    again = usd.ingest(package, out, wavelengths=GRID)
    assert (again["converted"], again["up_to_date"]) == (0, 1)


def test_a_changed_layer_reconverts_only_what_it_changes(usd, shop, tmp_path):
    out = tmp_path / "out"
    first = usd.ingest(shop / "shop.usda", out, wavelengths=GRID)
    assert first["converted"] == 3
    # The material's space changes; another texture's file is swapped for a new one.
    layer = Sdf.Layer.FindOrOpen(str(shop / "shop.usda"))
    layer.GetAttributeAtPath("/World/Painted.colorSpace:name").default = "lin_ap1_scene"
    shutil.copy(IMAGES / "grey_ramp8.png", shop / "tex" / "glow2.png")
    layer.GetAttributeAtPath("/World/Mat/Glow.inputs:file").default = Sdf.AssetPath("tex/glow2.png")
    layer.Save()
    second = usd.ingest(shop / "shop.usda", out, wavelengths=GRID)
    m = manifest(out)
    assert (second["converted"], second["up_to_date"]) == (2, 1)
    assert (m["paint.png"]["status"], m["paint.png"]["colorspace"]) == ("converted", "ACEScg")
    assert m["glow2.png"]["status"] == "converted" and m["albedo.png"]["status"] == "up_to_date"


def test_what_cannot_be_done_is_named_and_the_rest_converted(usd, shop, tmp_path):
    stage = Usd.Stage.Open(str(shop / "shop.usda"))
    stage.GetRootLayer().subLayerPaths.append("gone.usda")  # a layer that cannot be read
    texture(stage, "/World/Mat/Lost", "tex/lost.png")       # a missing asset
    UsdLux.DiskLight.Define(stage, "/World/Neg").CreateColorAttr(Gf.Vec3f(-1, 0, 0))
    stage.Save()
    out = tmp_path / "out"
    summary = usd.ingest(shop / "shop.usda", out, wavelengths=GRID)
    # Each is a failed record of the manifest, naming where: the rest is converted.
    assert summary["converted"] == 3 and summary["failed"] == 3
    failed = {r["origin"]["where"]: r for r in summary["failures"]}
    assert set(failed) == {"</World/Mat/Lost>.inputs:file", "</World/Neg>", "a layer of the stage"}
    assert "negative" in failed["</World/Neg>"]["message"]
    assert "gone.usda" in failed["a layer of the stage"]["message"]
    assert [r["prim"] for r in summary["light_failures"]] == ["/World/Neg"]
    assert len(summary["layer_failures"]) == 1 and "gone.usda" in summary["layer_failures"][0]
    m = manifest(out)
    assert m["shop.usda"]["status"] == "failed"  # the stage's own failures: its records
    assert sum(1 for line in (out / "spectralize-ingest.jsonl").read_text().splitlines()
               if '"failed"' in line and '"status"' in line) == 3


# --- The command line ---

needs_exe = pytest.mark.skipif(not EXE, reason="SPECTRALIZE_EXE is not set (ctest sets it)")


def run(*args, env=None):
    return subprocess.run([EXE, *map(str, args)], capture_output=True, text=True,
                          env=dict(os.environ, **(env or {})))


@needs_exe
def test_the_command_line_ingests_a_stage_as_python_does(usd, shop, tmp_path):
    cli, py = tmp_path / "cli", tmp_path / "py"
    done = run("ingest", shop / "shop.usda", "-o", cli, "--wavelengths", GRID)
    assert done.returncode == 0, done.stderr
    usd.ingest(shop / "shop.usda", py, wavelengths=GRID)
    a, b = manifest(cli), manifest(py)
    keys = ("status", "colorspace", "colorspace_reason", "mode", "mode_reason", "origin")
    assert {n: [r.get(k) for k in keys] for n, r in a.items()} == \
        {n: [r.get(k) for k in keys] for n, r in b.items()}
    for name, r in a.items():  # the same spectra, value for value (oiiotool: 0 tolerated)
        if r["status"] == "converted":
            same = subprocess.run(["oiiotool", "--fail", "0", "--warn", "0", "--diff", r["output"],
                                   b[name]["output"]], capture_output=True)
            assert same.returncode == 0, same.stdout
    assert json.loads((cli / "lights" / "World.Key.json").read_text())["values"] == \
        pytest.approx(json.loads((py / "lights" / "World.Key.json").read_text())["values"])
    layer = Usd.Stage.Open(str(cli / "spectral.usda"))
    assert os.path.isfile(layer.GetPrimAtPath("/World/Mat/Albedo")
                          .GetAttribute("spectralize:file").Get().resolvedPath)
    assert "USD stage" in done.stderr and "1 lights made, 0 failed" in done.stderr
    # A second run converts nothing.
    again = run("ingest", shop / "shop.usda", "-o", cli, "--wavelengths", GRID)
    assert again.returncode == 0 and "0 converted, 3 up to date" in again.stderr


@needs_exe
def test_the_command_line_exits_one_naming_what_failed(shop, tmp_path):
    stage = Usd.Stage.Open(str(shop / "shop.usda"))
    texture(stage, "/World/Mat/Lost", "tex/lost.png")
    UsdLux.DiskLight.Define(stage, "/World/Neg").CreateColorAttr(Gf.Vec3f(-1, 0, 0))
    stage.Save()
    out = tmp_path / "out"
    done = run("ingest", shop / "shop.usda", "-o", out, "--wavelengths", GRID)
    assert done.returncode == 1
    assert "</World/Mat/Lost>.inputs:file" in done.stderr
    assert "a negative colour or intensity: no light has it (</World/Neg>)" in done.stderr
    m = manifest(out)
    assert m["lost.png"]["status"] == "failed" and m["albedo.png"]["status"] == "converted"
    assert (out / "spectral.usda").is_file()  # the rest is done


@needs_exe
def test_the_command_line_without_openusd_says_what_to_install(shop, tmp_path):
    out = tmp_path / "out"
    shutil.copy(IMAGES / "colorchecker_srgb8.png", tmp_path / "other.png")
    # Debian's Python has no pxr; the module is found all the same.
    done = run("ingest", shop / "shop.usda", tmp_path / "other.png", "-o", out,
               env={"SPECTRALIZE_PYTHON": "/usr/bin/python3"})
    assert done.returncode == 1
    assert "usd-core" in done.stderr and "shop.usda" in done.stderr
    assert manifest(out)["other.png"]["status"] == "converted"  # the other input is done
    assert not (out / "spectral.usda").exists()


@needs_exe
def test_the_command_line_refuses_two_stages_and_a_missing_one(shop, tmp_path):
    done = run("ingest", shop / "shop.usda", shop / "shop.usda", "-o", tmp_path / "o")
    assert done.returncode == 2 and "one USD stage per batch" in done.stderr
    done = run("ingest", tmp_path / "nope.usdc", "-o", tmp_path / "o")
    assert done.returncode == 1 and "nope.usdc" in done.stderr and "no such file" in done.stderr
    done = run("ingest", shop / "shop.usda", "-o", tmp_path / "o", "--shard", "0/2")
    assert done.returncode == 2 and "one process" in done.stderr


# --- Stages as studios write them (cases a TD tried) ---

def test_a_file_declared_differently_in_two_places_is_converted_once_per_decision(usd, tmp_path):
    folder = tmp_path / "s"
    (folder / "tex").mkdir(parents=True)
    shutil.copy(IMAGES / "colorchecker_srgb8.png", folder / "tex" / "shared.png")
    stage = Usd.Stage.CreateNew(str(folder / "s.usda"))
    surface(stage, "/A", {"diffuseColor": ("/A/T", "tex/shared.png", "sRGB")})
    surface(stage, "/B", {"emissiveColor": ("/B/T", "tex/shared.png", None)})
    surface(stage, "/C", {"diffuseColor": ("/C/T", "tex/shared.png", "sRGB")})  # as /A
    stage.Save()
    out = tmp_path / "out"
    with pytest.warns(Warning, match="declared differently"):
        summary = usd.ingest(folder / "s.usda", out, wavelengths=GRID)
    assert summary["failed"] == 0 and summary["converted"] == 2
    layer = Usd.Stage.Open(str(out / "spectral.usda"))
    files = {p: layer.GetPrimAtPath(p).GetAttribute("spectralize:file").Get().resolvedPath
             for p in ("/A/T", "/B/T", "/C/T")}
    assert files["/A/T"] == files["/C/T"] != files["/B/T"]
    assert files["/A/T"].endswith("shared.reflectance-srgb_rec709_scene.exr")
    assert layer.GetPrimAtPath("/B/T").GetAttribute("spectralize:mode").Get() == "emission"
    assert all(os.path.isfile(f) for f in files.values())


@needs_exe
def test_a_stage_given_with_its_own_folder_takes_the_stages_decisions(shop, tmp_path):
    out = tmp_path / "out"
    done = run("ingest", shop / "shop.usda", shop, "-o", out, "--wavelengths", GRID)
    assert done.returncode == 0, done.stderr
    records = [json.loads(line) for line in (out / "spectralize-ingest.jsonl").read_text().splitlines()]
    albedo = [r for r in records if r.get("input", "").endswith("albedo.png")]
    assert [r["status"] for r in albedo] == ["converted"]
    assert albedo[0]["colorspace_reason"] == "</World/Mat/Albedo>.inputs:sourceColorSpace 'sRGB'"
    left = [r for r in records if r.get("kind") == "duplicate"]
    assert len(left) == 4 and all("a list line gives" in r["reason"] for r in left)


def test_inputs_are_followed_through_connections(usd, tmp_path):
    """A file promoted to the material's interface, a texture reaching an emissive input
    through a NodeGraph output and one reaching a surface colour through a multiply node; a
    file input with no asset at all fails, naming its prim."""
    folder = tmp_path / "s"
    (folder / "tex").mkdir(parents=True)
    for name in ("iface.png", "graph.png", "mult.png"):
        shutil.copy(IMAGES / "colorchecker_srgb8.png", folder / "tex" / name)
    stage = Usd.Stage.CreateNew(str(folder / "s.usda"))
    mat = UsdShade.Material.Define(stage, "/M")
    s = UsdShade.Shader.Define(stage, "/M/Surface")
    s.CreateIdAttr("UsdPreviewSurface")
    iface = mat.CreateInput("albedoFile", Sdf.ValueTypeNames.Asset)
    iface.Set("tex/iface.png")
    space = mat.CreateInput("albedoSpace", Sdf.ValueTypeNames.Token)
    space.Set("sRGB")
    t = texture(stage, "/M/Iface", "ignored.png")
    t.GetInput("file").ConnectToSource(iface)
    t.CreateInput("sourceColorSpace", Sdf.ValueTypeNames.Token).ConnectToSource(space)
    s.CreateInput("diffuseColor", Sdf.ValueTypeNames.Color3f).ConnectToSource(t.ConnectableAPI(), "rgb")
    graph = UsdShade.NodeGraph.Define(stage, "/M/Graph")
    glow = texture(stage, "/M/Graph/Glow", "tex/graph.png")
    out_port = graph.CreateOutput("glow", Sdf.ValueTypeNames.Color3f)
    out_port.ConnectToSource(glow.ConnectableAPI(), "rgb")
    s.CreateInput("emissiveColor", Sdf.ValueTypeNames.Color3f).ConnectToSource(out_port)
    mult = UsdShade.Shader.Define(stage, "/M/Mult")
    mult.CreateIdAttr("ND_multiply_color3")
    mult.CreateInput("in1", Sdf.ValueTypeNames.Color3f).ConnectToSource(
        texture(stage, "/M/MultTex", "tex/mult.png").ConnectableAPI(), "rgb")
    mult.CreateOutput("out", Sdf.ValueTypeNames.Color3f)
    s2 = UsdShade.Shader.Define(stage, "/M/Coat")
    s2.CreateIdAttr("UsdPreviewSurface")
    s2.CreateInput("diffuseColor", Sdf.ValueTypeNames.Color3f).ConnectToSource(mult.ConnectableAPI(), "out")
    empty = UsdShade.Shader.Define(stage, "/M/Empty")
    empty.CreateIdAttr("UsdUVTexture")
    empty.CreateInput("file", Sdf.ValueTypeNames.Asset)
    stage.Save()
    got = {os.path.basename(r.get("input", r["prim"])): r for r in usd.textures(folder / "s.usda")}
    assert (got["iface.png"]["colorspace"], got["iface.png"]["mode"]) == ("srgb_rec709_scene", "reflectance")
    assert got["iface.png"]["value_from"] == "/M.inputs:albedoFile"
    assert got["graph.png"]["mode"] == "emission"
    assert got["mult.png"]["mode"] == "reflectance"
    assert got["Empty"]["failure"] == "/M/Empty.inputs:file: no asset authored"
    summary = usd.ingest(folder / "s.usda", tmp_path / "out", wavelengths=GRID)
    assert summary["converted"] == 3 and summary["failed"] == 1
    assert summary["failures"][0]["origin"]["where"] == "</M/Empty>.inputs:file"


def test_an_asset_attributes_own_colour_space_is_the_stages_word(usd, tmp_path):
    folder = tmp_path / "s"
    folder.mkdir()
    shutil.copy(IMAGES / "colorchecker_srgb8.png", folder / "meta.png")
    stage = Usd.Stage.CreateNew(str(folder / "s.usda"))
    surface(stage, "/M", {"diffuseColor": ("/M/T", "meta.png", None)})
    stage.GetPrimAtPath("/M/T").GetAttribute("inputs:file").SetColorSpace("lin_ap1_scene")
    stage.Save()
    [r] = usd.textures(folder / "s.usda")
    assert r["colorspace"] == "lin_ap1_scene"
    assert r["colorspace_reason"] == "colorSpace 'lin_ap1_scene' of </M/T>.inputs:file"


def test_files_outside_the_stages_folder_keep_their_own_names_apart(usd, tmp_path):
    for lib in ("libA", "libB"):
        (tmp_path / lib).mkdir()
        shutil.copy(IMAGES / "colorchecker_srgb8.png", tmp_path / lib / "albedo.png")
    folder = tmp_path / "s"
    folder.mkdir()
    stage = Usd.Stage.CreateNew(str(folder / "s.usda"))
    surface(stage, "/A", {"diffuseColor": ("/A/T", "../libA/albedo.png", "sRGB")})
    surface(stage, "/B", {"diffuseColor": ("/B/T", str(tmp_path / "libB" / "albedo.png"), "sRGB")})
    stage.Save()
    out = tmp_path / "out"
    summary = usd.ingest(folder / "s.usda", out, wavelengths=GRID)
    assert summary["converted"] == 2 and summary["failed"] == 0
    for lib in ("libA", "libB"):
        assert (out / "external" / str(tmp_path / lib / "albedo.exr").lstrip("/")).is_file()


def test_an_instanced_texture_is_converted_and_said_not_to_be_in_the_layer(usd, tmp_path):
    folder = tmp_path / "s"
    folder.mkdir()
    shutil.copy(IMAGES / "colorchecker_srgb8.png", folder / "a.png")
    asset = Usd.Stage.CreateNew(str(folder / "thing.usda"))
    asset.SetDefaultPrim(asset.DefinePrim("/Thing", "Xform"))
    surface(asset, "/Thing/Mat", {"diffuseColor": ("/Thing/Mat/T", "a.png", "sRGB")})
    asset.Save()
    stage = Usd.Stage.CreateNew(str(folder / "s.usda"))
    for name in ("/World/Inst0", "/World/Inst1"):
        prim = stage.DefinePrim(name)
        prim.GetReferences().AddReference("./thing.usda")
        prim.SetInstanceable(True)
    stage.Save()
    with pytest.warns(Warning, match="under an instance"):
        summary = usd.ingest(folder / "s.usda", tmp_path / "out", wavelengths=GRID)
    assert summary["converted"] == 1
    assert sorted(summary["not_in_layer"]) == [
        "</World/Inst%d/Mat/T>: under an instance, where a layer's opinions are ignored: its "
        "spectra are not in the layer" % i for i in (0, 1)]


def test_lights_take_any_name_the_config_has_and_keep_their_own_files(usd, tmp_path):
    stage = Usd.Stage.CreateNew(str(tmp_path / "l.usda"))
    for path, space in (("/Cfg", "ACEScg"), ("/Ban", "banana")):
        Usd.ColorSpaceAPI.Apply(stage.DefinePrim(path)).CreateColorSpaceNameAttr(space)
        UsdLux.SphereLight.Define(stage, path + "/L")
    UsdLux.SphereLight.Define(stage, "/World/A__B")
    UsdLux.SphereLight.Define(stage, "/World/A/B")
    stage.Save()
    records = {r["prim"]: r for r in usd.lights(tmp_path / "l.usda")}
    assert records["/Cfg/L"]["basis"] == "D60"  # ACEScg by its name: the ACES white
    assert "banana" in records["/Ban/L"]["failure"] and "colorSpace:name" in records["/Ban/L"]["failure"]
    summary = usd.ingest(tmp_path / "l.usda", tmp_path / "out", wavelengths=GRID)
    names = sorted(os.path.basename(r["file"]) for r in summary["lights"] if "file" in r)
    assert names == ["Cfg.L.json", "World.A.B.json", "World.A__B.json"]


@needs_exe
def test_a_layer_that_would_replace_a_file_of_the_stage_is_refused(tmp_path):
    folder, other = tmp_path / "s", tmp_path / "o"
    folder.mkdir()
    other.mkdir()
    shutil.copy(IMAGES / "hdri_sunset_256x128.exr", folder / "sky.exr")
    # A layer of the stage where the output's spectral.usda would go.
    sub = Usd.Stage.CreateNew(str(other / "spectral.usda"))
    sub.DefinePrim("/Extra")
    sub.Save()
    stage = Usd.Stage.CreateNew(str(folder / "spectral.usda"))
    UsdLux.DomeLight.Define(stage, "/Sky").CreateTextureFileAttr("sky.exr")
    stage.GetRootLayer().subLayerPaths.append("../o/spectral.usda")
    stage.Save()
    before = {p: p.read_bytes() for p in (folder / "spectral.usda", other / "spectral.usda")}
    done = run("ingest", folder / "spectral.usda", "-o", other, "--wavelengths", GRID)
    assert done.returncode == 1
    assert "is a file of the stage" in done.stderr and "spectral.usda" in done.stderr
    # The stage's own folder as the output: refused before any work.
    done = run("ingest", folder / "spectral.usda", "-o", str(folder) + "/.", "--wavelengths", GRID)
    assert done.returncode == 2 and "is the folder of the USD stage" in done.stderr
    assert {p: p.read_bytes() for p in before} == before
    assert sorted(os.listdir(folder)) == ["sky.exr", "spectral.usda"]


@needs_exe
def test_a_python_that_cannot_start_fails_the_stage_not_the_batch(shop, tmp_path):
    shutil.copy(IMAGES / "colorchecker_srgb8.png", tmp_path / "other.png")
    out = tmp_path / "out"
    done = run("ingest", shop / "shop.usda", tmp_path / "other.png", "-o", out,
               env={"SPECTRALIZE_PYTHON": str(tmp_path / "no-python")})
    assert done.returncode == 1 and "cannot start the Python" in done.stderr
    assert manifest(out)["other.png"]["status"] == "converted"


def test_a_texture_chosen_by_a_variant_is_pointed_at_inside_that_variant(usd, tmp_path):
    folder = tmp_path / "s"
    (folder / "tex").mkdir(parents=True)
    for name in ("red.png", "blue.png"):
        shutil.copy(IMAGES / "colorchecker_srgb8.png", folder / "tex" / name)
    stage = Usd.Stage.CreateNew(str(folder / "s.usda"))
    surface(stage, "/V", {"diffuseColor": ("/V/T", "tex/red.png", "sRGB")})
    stage.GetPrimAtPath("/V/T").GetAttribute("inputs:file").Clear()
    look = stage.GetPrimAtPath("/V").GetVariantSets().AddVariantSet("look")
    for name in ("red", "blue"):
        look.AddVariant(name)
        look.SetVariantSelection(name)
        with look.GetVariantEditContext():
            stage.GetPrimAtPath("/V/T").GetAttribute("inputs:file").Set(
                Sdf.AssetPath("tex/%s.png" % name))
    look.SetVariantSelection("blue")
    stage.Save()
    usd.ingest(folder / "s.usda", tmp_path / "out", wavelengths=GRID)
    layered = Usd.Stage.Open(str(tmp_path / "out" / "spectral.usda"))
    t = layered.GetPrimAtPath("/V/T")
    assert t.GetAttribute("spectralize:file").Get().path.endswith("blue.exr")
    # Another variant selected: the layer's opinion, inside the blue variant, no longer holds.
    layered.GetPrimAtPath("/V").GetVariantSets().GetVariantSet("look").SetVariantSelection("red")
    assert layered.GetPrimAtPath("/V/T").GetAttribute("inputs:file").Get().path == "tex/red.png"
    assert not layered.GetPrimAtPath("/V/T").GetAttribute("spectralize:file").HasValue()


def test_a_dome_lights_file_colour_space_metadata_is_the_stages_word(usd, tmp_path):
    shutil.copy(IMAGES / "hdri_sunset_256x128.exr", tmp_path / "sky.exr")
    stage = Usd.Stage.CreateNew(str(tmp_path / "s.usda"))
    dome = UsdLux.DomeLight.Define(stage, "/Dome")
    Usd.ColorSpaceAPI.Apply(dome.GetPrim()).CreateColorSpaceNameAttr("lin_ap1_scene")
    dome.CreateTextureFileAttr("sky.exr").SetColorSpace("lin_rec2020_scene")
    stage.Save()
    [r] = usd.textures(tmp_path / "s.usda")
    assert (r["colorspace"], r["mode"]) == ("lin_rec2020_scene", "emission")


def test_temporaries_a_killed_run_left_are_removed_and_a_live_ones_kept(usd, shop, tmp_path):
    import fcntl
    out = tmp_path / "out"
    (out / "lights").mkdir(parents=True)
    stale = [out / ".spectral.usda.spectralize-aB3dE9.tmp",
             out / "lights" / ".World.Key.json.spectralize-Zz9Yy8.tmp"]
    for p in stale:
        p.write_text("left by a killed run")
    live = out / ".spectral.usda.spectralize-LiVe01.tmp"
    live.write_text("being written")
    with open(live) as held:
        fcntl.flock(held, fcntl.LOCK_EX)
        usd.ingest(shop / "shop.usda", out, wavelengths=GRID)
        assert live.exists()
    assert not any(p.exists() for p in stale)


def test_udim_tiles_in_a_package_are_expanded_there(usd, tmp_path):
    # A package holding its layer and two tiles (written with OpenUSD's zip writer): each tile
    # is read from the package, never a file of the same pattern beside it on disk; a pattern
    # with no tile there is named with the package.
    folder = tmp_path / "a"
    (folder / "tex").mkdir(parents=True)
    for tile in ("1001", "1002"):
        shutil.copy(IMAGES / "grey_ramp8.png", folder / "tex" / ("t.%s.png" % tile))
    stage = Usd.Stage.CreateNew(str(folder / "a.usda"))
    surface(stage, "/M", {"diffuseColor": ("/M/T", "tex/t.<UDIM>.png", "sRGB")})
    texture(stage, "/M/Lost", "tex/lost.<UDIM>.png")
    stage.Save()
    package = tmp_path / "a.usdz"
    writer = Sdf.ZipFileWriter.CreateNew(str(package))
    for name in ("a.usda", "tex/t.1001.png", "tex/t.1002.png"):
        writer.AddFile(str(folder / name), name)
    writer.Save()
    shutil.rmtree(folder)
    (tmp_path / "tex").mkdir()  # a decoy beside the package
    shutil.copy(IMAGES / "grey_ramp8.png", tmp_path / "tex" / "t.1003.png")
    records = usd.textures(package)
    tiles = sorted(r["input"] for r in records if r["prim"] == "/M/T")
    assert tiles == ["%s[tex/t.%s.png]" % (package, t) for t in ("1001", "1002")]
    (lost,) = [r for r in records if r["prim"] == "/M/Lost"]
    assert lost["failure"] == "/M/Lost.inputs:file: no UDIM tile 'tex/lost.<UDIM>.png' inside " \
                              "the package '%s'" % package
    summary = usd.ingest(package, tmp_path / "out", wavelengths=GRID)
    assert summary["converted"] == 2 and summary["failed"] == 1
    layer = Usd.Stage.Open(str(tmp_path / "out" / "spectral.usda"))
    files = layer.GetPrimAtPath("/M/T").GetAttribute("spectralize:files").Get()
    assert len(files) == 2 and all(os.path.isfile(f.resolvedPath) for f in files)


@needs_exe
def test_an_output_that_is_no_folder_is_named_as_ingest_names_it(shop, tmp_path):
    (tmp_path / "afile").write_text("x")
    done = run("ingest", shop / "shop.usda", "-o", tmp_path / "afile")
    assert done.returncode == 1
    assert "afile': is not a folder (ingest writes a tree of files into a folder)" in done.stderr
    assert "Errno" not in done.stderr


@needs_exe
def test_failed_records_of_the_stage_name_no_output_and_reasons_name_what_decides(shop, tmp_path):
    stage = Usd.Stage.Open(str(shop / "shop.usda"))
    UsdLux.DiskLight.Define(stage, "/World/Neg").CreateColorAttr(Gf.Vec3f(-1, 0, 0))
    s = UsdShade.Shader(stage.GetPrimAtPath("/World/Mat/Surface"))
    s.CreateInput("opacity", Sdf.ValueTypeNames.Float).ConnectToSource(
        UsdShade.Shader(stage.GetPrimAtPath("/World/Mat/Albedo")).ConnectableAPI(), "r")
    stage.Save()
    out = tmp_path / "out"
    run("ingest", shop / "shop.usda", "-o", out, "--wavelengths", GRID)
    records = [json.loads(line) for line in (out / "spectralize-ingest.jsonl").read_text().splitlines()]
    [neg] = [r for r in records if r.get("status") == "failed"]
    assert "output" not in neg
    [albedo] = [r for r in records if r.get("input", "").endswith("albedo.png")]
    assert albedo["mode_reason"] == ("feeds a surface colour: </World/Mat/Surface>.inputs:"
                                     "diffuseColor (also </World/Mat/Surface>.inputs:opacity)")


def test_an_animated_file_and_light_are_converted_at_every_time_and_the_layer_follows(usd, tmp_path):
    # A texture sequence (the file's asset path time-sampled) and a light whose colour is:
    # every file the sequence names is converted once, and the layer's spectralize:file and
    # spectralize:values hold, at each time, what the stage names there.
    folder = tmp_path / "seq"
    (folder / "tex").mkdir(parents=True)
    for n in (1, 2, 3):
        shutil.copy(IMAGES / "colorchecker_srgb8.png", folder / "tex" / ("frame.%d.png" % n))
    stage = Usd.Stage.CreateNew(str(folder / "seq.usda"))
    surface(stage, "/Mat", {"diffuseColor": ("/Mat/Tex", "tex/frame.1.png", "sRGB")})
    file = UsdShade.Shader(stage.GetPrimAtPath("/Mat/Tex")).GetInput("file")
    for t, n in ((1, 1), (2, 2), (3, 2), (4, 3), (5, 9)):  # frame 9 is missing
        file.Set(Sdf.AssetPath("tex/frame.%d.png" % n), t)
    light = UsdLux.SphereLight.Define(stage, "/Blink")
    light.CreateColorAttr().Set(Gf.Vec3f(1.0, 0.2, 0.2), 0.0)
    light.GetColorAttr().Set(Gf.Vec3f(0.2, 0.2, 1.0), 10.0)
    stage.Save()
    out = tmp_path / "out"
    summary = usd.ingest(folder / "seq.usda", out, wavelengths=GRID)
    assert summary["converted"] == 3 and summary["failed"] == 1
    m = manifest(out)
    assert m["frame.1.png"]["origin"]["times"] == ["default", 1.0]
    assert m["frame.2.png"]["origin"]["where"] == "</Mat/Tex>.inputs:file at times 2, 3"
    assert m["frame.9.png"]["status"] == "failed"
    assert "</Mat/Tex>.inputs:file at time 5" in m["frame.9.png"]["message"]
    # The layer, composed: at each time the spectral file of the file the stage names then.
    composed = Usd.Stage.Open(str(out / "spectral.usda"))
    tex = composed.GetPrimAtPath("/Mat/Tex")
    original = tex.GetAttribute("inputs:file")
    spectral = tex.GetAttribute("spectralize:file")
    for t in (Usd.TimeCode.Default(), Usd.TimeCode(1), Usd.TimeCode(2.5), Usd.TimeCode(4)):
        got = pathlib.Path(spectral.Get(t).resolvedPath)
        assert got.is_file() and got.parent == out / "tex"
        assert got.stem == pathlib.Path(original.Get(t).path).stem, t
    # The light: one spectrum per time of its colour, the same in the layer and its file.
    record = json.loads((out / "lights" / "Blink.json").read_text())
    assert record["times"] == [0.0, 10.0] and len(record["values"]) == 2
    assert record["values"][0] != pytest.approx(record["values"][1])
    values = composed.GetPrimAtPath("/Blink").GetAttribute("spectralize:values")
    assert values.GetTimeSamples() == [0.0, 10.0]
    for t, row in zip(record["times"], record["values"]):
        assert list(values.Get(t)) == pytest.approx(row, rel=1e-6)


def test_a_stage_that_names_another_colour_configuration_is_told(usd, shop, tmp_path, monkeypatch):
    # colorConfiguration names the OCIO config the stage's colour-space names belong to: read
    # in another config, a warning names both and the flag that reads them in the stage's.
    monkeypatch.delenv("OCIO", raising=False)  # the built-in default is the config in use
    shipped = SOURCE / "ocio_configs" / "spectralize.ocio"
    shutil.copy(shipped, shop / "studio.ocio")
    stage = Usd.Stage.Open(str(shop / "shop.usda"))
    stage.SetColorConfiguration(Sdf.AssetPath("studio.ocio"))
    stage.Save()
    with pytest.warns(Warning, match="colorConfiguration"):
        summary = usd.ingest(shop / "shop.usda", tmp_path / "a", wavelengths=GRID)
    (said,) = [c for c in summary["conflicts"] if "colorConfiguration" in c]
    assert "'studio.ocio'" in said and "the built-in default config" in said
    assert "--config '%s'" % (shop / "studio.ocio") in said
    # Read in that very config: nothing to say.
    summary = usd.ingest(shop / "shop.usda", tmp_path / "b", wavelengths=GRID,
                         config=str(shop / "studio.ocio"))
    assert not [c for c in summary["conflicts"] if "colorConfiguration" in c]


@needs_exe
def test_the_command_line_starts_python_once_per_stage(shop, tmp_path):
    # Python and OpenUSD take about a second to start: the stage's list and its layer are
    # written by one helper process, not two.
    log = tmp_path / "starts.log"
    wrapper = tmp_path / "python"
    wrapper.write_text('#!/bin/sh\necho started >> "%s"\nexec "%s" "$@"\n' % (log, sys.executable))
    wrapper.chmod(0o755)
    out = tmp_path / "out"
    done = run("ingest", shop / "shop.usda", "-o", out, "--wavelengths", GRID,
               env={"SPECTRALIZE_PYTHON": str(wrapper)})
    assert done.returncode == 0, done.stderr
    assert log.read_text().splitlines() == ["started"]
    assert (out / "spectral.usda").is_file() and manifest(out)["albedo.png"]["status"] == "converted"


def serve(stage, out, listing, command):
    """spectralize.usd's command-line half as the tool runs it: "ready" read from its fd 3,
    then `command` (bytes; None: nothing) written to its fd 4 and the pipe closed."""
    ready_r, ready_w = os.pipe()
    cmd_r, cmd_w = os.pipe()

    def at_3_and_4():  # (moved above 4 first: either may be 3 or 4 here)
        high = [fcntl.fcntl(fd, fcntl.F_DUPFD_CLOEXEC, 10) for fd in (ready_w, cmd_r)]
        for fd, at in zip(high, (3, 4)):
            os.dup2(fd, at)

    helper = subprocess.Popen(
        [sys.executable, "-c", "import sys, spectralize.usd as u; sys.exit(u._main(sys.argv[1:]))",
         "serve", str(stage), str(out), str(listing), json.dumps({"wavelengths": GRID}), "1"],
        preexec_fn=at_3_and_4, close_fds=False, stderr=subprocess.PIPE)
    os.close(ready_w)
    os.close(cmd_r)
    with os.fdopen(ready_r, "rb") as r:
        said = r.read()
    with os.fdopen(cmd_w, "wb") as w:
        if command is not None:
            w.write(command)
    return said, helper.wait(timeout=120), helper.stderr.read().decode()


def test_the_helper_writes_the_layer_only_when_told(usd, shop, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    # Told nothing (the tool ended the batch early): the list written, no layer.
    said, status, err = serve(shop / "shop.usda", out, tmp_path / "list.jsonl", None)
    assert said == b"ready\n" and status == 0, err
    assert "albedo.png" in (tmp_path / "list.jsonl").read_text()
    assert not (out / "spectral.usda").exists()
    # Told to finish from a manifest: the layer, pointing at what the manifest says.
    summary = usd.ingest(shop / "shop.usda", tmp_path / "made", wavelengths=GRID)
    (out / "spectral.usda").unlink(missing_ok=True)
    said, status, err = serve(shop / "shop.usda", tmp_path / "made", tmp_path / "list.jsonl",
                              b"finish\n" + os.fsencode(summary["manifest"]))
    assert said == b"ready\n" and status == 0, err
    assert "layer" in err and (tmp_path / "made" / "spectral.usda").is_file()


@needs_exe
def test_an_interrupted_command_line_leaves_no_layer_and_no_helper(tmp_path):
    # The tool is stopped (SIGTERM, to it alone) while the stage's texture is converted: its
    # helper, waiting to write the layer, ends with it, and neither layer nor output is left.
    import signal
    import time
    folder = tmp_path / "s"
    folder.mkdir()
    subprocess.run(["oiiotool", "--pattern", "noise:type=uniform", "2000x2000", "3", "-d", "uint8",
                    "-o", str(folder / "noise.png")], check=True)
    stage = Usd.Stage.CreateNew(str(folder / "s.usda"))
    surface(stage, "/M", {"diffuseColor": ("/M/T", "noise.png", "sRGB")})
    stage.Save()
    pid_file, temporaries = tmp_path / "helper.pid", tmp_path / "tmp"
    temporaries.mkdir()
    wrapper = tmp_path / "python"
    wrapper.write_text('#!/bin/sh\necho $$ > "%s"\nexec "%s" "$@"\n' % (pid_file, sys.executable))
    wrapper.chmod(0o755)
    out = tmp_path / "out"
    tool = subprocess.Popen([EXE, "ingest", str(folder / "s.usda"), "-o", str(out), "-q",
                             "--wavelengths", GRID], stderr=subprocess.PIPE,
                            env=dict(os.environ, SPECTRALIZE_PYTHON=str(wrapper),
                                     TMPDIR=str(temporaries)))
    deadline = time.time() + 60
    while time.time() < deadline and not any(
            p.stat().st_size > 0 for p in temporaries.glob("spectralize-usd-*.jsonl")):
        time.sleep(0.02)  # the helper has written the stage's list: the conversion begins
    time.sleep(0.3)
    assert tool.poll() is None, "the conversion ended before it could be interrupted"
    tool.send_signal(signal.SIGTERM)
    assert tool.wait(timeout=60) != 0
    helper = int(pid_file.read_text())
    for _ in range(500):  # gone, or a zombie no one reaps (the tool's parent is gone)
        try:
            if "State:\tZ" in pathlib.Path("/proc/%d/status" % helper).read_text():
                break
        except FileNotFoundError:
            break
        time.sleep(0.02)
    else:
        pytest.fail("the helper outlived the tool")
    assert not (out / "spectral.usda").exists()
    assert not list(out.rglob("*.exr")) and not list(out.rglob("*.tmp"))
    assert not list(temporaries.iterdir())  # the stage's list went with the tool
