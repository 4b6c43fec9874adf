"""spectralize.usd: the textures of an OpenUSD stage, decided as a TD would (docs/guide/usd.md).

textures(stage) opens a stage (every layer, reference and payload composed) and returns each
texture file it uses: the files of UsdUVTexture shaders (UDIM tiles expanded) and of DomeLights,
with the colour space the stage declares for them and what they feed:

- colour space: UsdUVTexture's inputs:sourceColorSpace ("raw": data; "sRGB":
  srgb_rec709_scene), else the UsdColorSpaceAPI space in force at the shader (the nearest
  ancestor, the prim included, that applies the API and authors colorSpace:name; "raw",
  "identity" and "data" are data); where the stage declares nothing, None: the file's own tags
  and the config's file rules decide, as for any file;
- light, surface or data: a DomeLight's texture and an emissive colour input
  (emissiveColor, emission_color) are light; a surface colour input (diffuseColor, base_color,
  specularColor, ...) a surface; any other input a texture feeds (normal, roughness, metallic,
  opacity, displacement, occlusion, ...) makes it data, never spectralized; a texture that feeds
  nothing is left to the file's own decision.

Each record is a dict: "input" (the file), "asset" (as authored), "prim" and "attribute" (where
it is named), "feeds" (the inputs it is connected to, "</Mat/Surface>.inputs:diffuseColor"),
"colorspace" and "colorspace_reason", "mode" ("reflectance", "emission", "data" or None) and
"mode_reason"; a texture whose file is missing has "failure" instead of "input". OpenUSD's
Python bindings (pip install usd-core) are imported when a stage is opened, not before.
"""

import glob
import json
import os
import re
import tempfile

__all__ = ["textures", "list_line", "ingest", "lights"]

# What a texture feeds, by the consumer input's name (UsdPreviewSurface, MaterialX
# standard_surface and OpenPBR spellings).
SURFACE_COLOUR_INPUTS = {
    "diffuseColor", "specularColor", "base_color", "specular_color", "coat_color",
    "sheen_color", "subsurface_color", "transmission_color", "base_color_map",
}
EMISSIVE_COLOUR_INPUTS = {"emissiveColor", "emission_color"}
# UsdColorSpaceAPI names (and sourceColorSpace words) that are not colour.
DATA_SPACES = {"raw", "identity", "data"}
UDIM = "<UDIM>"


def _pxr():
    try:
        from pxr import Sdf, Usd, UsdLux, UsdShade  # noqa: F401
    except ImportError as e:
        raise ImportError("spectralize.usd needs OpenUSD's Python bindings (pip install "
                          "usd-core): " + str(e)) from e
    return Sdf, Usd, UsdLux, UsdShade


def _open(stage):
    Sdf, Usd, _, _ = _pxr()
    if isinstance(stage, Usd.Stage):
        return stage
    path = os.fspath(stage)
    if not os.path.isfile(path):
        raise OSError("USD stage '%s': no such file" % path)
    try:
        opened = Usd.Stage.Open(path, Usd.Stage.LoadAll)
    except Exception as e:  # pxr raises Tf errors as RuntimeError and friends
        raise OSError("USD stage '%s': %s" % (path, str(e).strip())) from e
    if not opened:
        raise OSError("USD stage '%s': OpenUSD cannot open it" % path)
    return opened


def _space_in_force(prim, undeclared, undeclared_reason):
    """The colour space the stage declares for `prim` (UsdColorSpaceAPI, "data" for a data
    space) and why; (`undeclared`, `undeclared_reason`) where it declares none."""
    declared, declarer = _declared_space(prim)
    if not declared:
        return undeclared, undeclared_reason
    return ("data" if declared in DATA_SPACES else declared,
            "colorSpace:name '%s' of <%s> (UsdColorSpaceAPI)" % (declared, declarer.GetPath()))


NO_DECLARATION = "the stage declares none: the file's own tags and the config's rules"


def _declared_space(prim):
    """The UsdColorSpaceAPI name in force at `prim` and the prim that authors it, or (None,
    None) where no ancestor (the prim included) declares one."""
    _, Usd, _, _ = _pxr()
    while prim and not prim.IsPseudoRoot():
        if prim.HasAPI(Usd.ColorSpaceAPI):
            attr = Usd.ColorSpaceAPI(prim).GetColorSpaceNameAttr()
            if attr and attr.HasAuthoredValue():
                return str(attr.Get()), prim
        prim = prim.GetParent()
    return None, None


def _consumers(stage):
    """For each prim a shader input is connected to: the inputs that read it, as
    (consumer prim, input name)."""
    _, Usd, _, UsdShade = _pxr()
    fed = {}
    for prim in stage.Traverse(Usd.TraverseInstanceProxies()):
        connectable = UsdShade.ConnectableAPI(prim)
        if not connectable:
            continue
        for inp in connectable.GetInputs():
            for source in inp.GetConnectedSources()[0]:
                fed.setdefault(source.source.GetPrim().GetPath(), []).append(
                    (prim, inp.GetBaseName()))
    return fed


def _resolved(attr, asset):
    """The files an asset path names: its resolved path, or the UDIM tiles (1001-1999) that
    exist next to where the layer that authors it says."""
    if UDIM not in asset.path:
        return [asset.resolvedPath] if asset.resolvedPath else []
    layer = None
    for spec in attr.GetPropertyStack():
        if spec.default is not None:
            layer = spec.layer
            break
    # Relative to the layer that authors it (OpenUSD's default resolver anchors the same way).
    anchored = asset.path
    if layer is not None and not os.path.isabs(anchored) and layer.realPath:
        anchored = os.path.normpath(os.path.join(os.path.dirname(layer.realPath), anchored))
    pattern = re.escape(anchored).replace(re.escape(UDIM), r"(1\d\d\d)")
    tiles = [p for p in glob.glob(anchored.replace(UDIM, "1[0-9][0-9][0-9]"))
             if re.fullmatch(pattern, p)]
    return sorted(tiles)


def _texture_records(prim, attr, decide):
    value = attr.Get()
    record = {"asset": value.path if value else "", "prim": str(prim.GetPath()),
              "attribute": attr.GetName()}
    record.update(decide())
    files = _resolved(attr, value) if value else []
    if not files:
        failed = dict(record)
        failed["failure"] = "%s.%s: asset '%s' not found" % (record["prim"], record["attribute"],
                                                              record["asset"])
        return [failed]
    out = []
    for f in files:
        r = dict(record)
        r["input"] = f
        out.append(r)
    return out


def _uv_texture_decision(shader_prim, fed):
    _, _, _, UsdShade = _pxr()
    shader = UsdShade.Shader(shader_prim)
    where = "<%s>" % shader_prim.GetPath()
    feeds = ["<%s>.inputs:%s" % (p.GetPath(), name) for p, name in fed.get(shader_prim.GetPath(), [])]
    names = {name for _, name in fed.get(shader_prim.GetPath(), [])}
    source = shader.GetInput("sourceColorSpace")
    word = str(source.Get()) if source and source.Get() else "auto"
    d = {"feeds": feeds}
    if word == "raw":
        d["colorspace"], d["colorspace_reason"] = "data", where + ".inputs:sourceColorSpace 'raw'"
    elif word == "sRGB":
        d["colorspace"] = "srgb_rec709_scene"
        d["colorspace_reason"] = where + ".inputs:sourceColorSpace 'sRGB'"
    else:
        d["colorspace"], d["colorspace_reason"] = _space_in_force(shader_prim, None,
                                                                  NO_DECLARATION)
    if d["colorspace"] == "data":
        d["mode"], d["mode_reason"] = "data", "its colour space is data (%s)" % d["colorspace_reason"]
    elif names & EMISSIVE_COLOUR_INPUTS:
        d["mode"], d["mode_reason"] = "emission", "feeds an emissive colour: " + ", ".join(feeds)
    elif names & SURFACE_COLOUR_INPUTS:
        d["mode"], d["mode_reason"] = "reflectance", "feeds a surface colour: " + ", ".join(feeds)
    elif names:
        d["mode"], d["mode_reason"] = "data", "feeds no colour: " + ", ".join(feeds)
    else:
        d["mode"], d["mode_reason"] = None, "feeds nothing: the file's own decision"
    return d


def _dome_decision(light_prim):
    colorspace, reason = _space_in_force(light_prim, None, NO_DECLARATION)
    return {"feeds": [], "mode": "emission",
            "mode_reason": "the texture of DomeLight <%s>" % light_prim.GetPath(),
            "colorspace": colorspace, "colorspace_reason": reason}


def textures(stage):
    """Every texture file `stage` (a path or a Usd.Stage) uses, decided: a list of dicts (see
    the module's doc), in the stage's order. OSError for a stage that cannot be opened.
    Cost: composing the stage, O(prims)."""
    _, Usd, UsdLux, UsdShade = _pxr()
    stage = _open(stage)
    fed = _consumers(stage)
    out = []
    for prim in stage.Traverse(Usd.TraverseInstanceProxies()):
        if prim.IsA(UsdShade.Shader):
            shader = UsdShade.Shader(prim)
            if shader.GetShaderId() != "UsdUVTexture":
                continue
            file_input = shader.GetInput("file")
            if not file_input:
                continue
            out += _texture_records(prim, file_input.GetAttr(),
                                    lambda: _uv_texture_decision(prim, fed))
        elif prim.IsA(UsdLux.DomeLight) or prim.IsA(UsdLux.DomeLight_1):
            attr = prim.GetAttribute("inputs:texture:file")
            if attr and attr.HasAuthoredValue():
                out += _texture_records(prim, attr, lambda: _dome_decision(prim))
    return out


def list_line(record):
    """A record as a line of `ingest --inputs-from` (a JSON object: the file and the settings
    the stage decided; data as the config's data role), or None for a record without a file.
    Cost: O(1)."""
    if "input" not in record:
        return None
    line = {"input": record["input"]}
    if record.get("mode") == "data":
        line["colorspace"] = "data"
        return line
    if record.get("colorspace"):
        line["colorspace"] = record["colorspace"]
    if record.get("mode"):
        line["mode"] = record["mode"]
    return line


# The options of ingest() that shape a light's spectrum too (spectra() takes them).
LIGHT_OPTIONS = ("wavelengths", "observer", "model", "filter", "curvature", "config")


def _write_atomically(path, write):
    """Writes `path` through a temporary beside it, renamed when complete."""
    folder = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(prefix=".spectralize-", suffix=os.path.splitext(path)[1],
                               dir=folder)
    os.close(fd)
    try:
        write(tmp)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise


def _light_file_name(prim):
    return prim.strip("/").replace("/", "__") or "root"


def _custom(spec, name, type_name):
    """A custom attribute `name` of type Sdf.ValueTypeNames.<type_name> on the prim spec."""
    Sdf, _, _, _ = _pxr()
    return Sdf.AttributeSpec(spec, name, getattr(Sdf.ValueTypeNames, type_name),
                             Sdf.VariabilityVarying, True)


def _override_layer(path, root_layer, textures_done, light_records):
    """spectral.usda: the original stage as a sublayer, and overs that only add attributes in
    the spectralize: namespace (docs/guide/files.md)."""
    Sdf, _, _, _ = _pxr()
    folder = os.path.dirname(os.path.abspath(path))

    def write(tmp):
        layer = Sdf.Layer.CreateAnonymous(".usda")
        layer.subLayerPaths.append(os.path.relpath(root_layer, folder))
        for prim, entries in textures_done.items():
            spec = Sdf.CreatePrimInLayer(layer, prim)
            spec.specifier = Sdf.SpecifierOver
            outputs = [os.path.relpath(e["output"], folder) for e in entries]
            if len(outputs) == 1:
                attr = _custom(spec, "spectralize:file", "Asset")
                attr.default = Sdf.AssetPath(outputs[0])
            else:  # UDIM tiles
                attr = _custom(spec, "spectralize:files", "AssetArray")
                attr.default = Sdf.AssetPathArray(outputs)
            for key in ("mode", "colorspace"):
                a = _custom(spec, "spectralize:" + key, "String")
                a.default = str(entries[0][key])
        for r in light_records:
            if "values" not in r:
                continue
            spec = Sdf.CreatePrimInLayer(layer, r["prim"])
            spec.specifier = Sdf.SpecifierOver
            for key, values in (("wavelengths", r["wavelengths"]), ("values", r["values"])):
                a = _custom(spec, "spectralize:" + key, "FloatArray")
                a.default = [float(v) for v in values]
            a = _custom(spec, "spectralize:basis", "String")
            a.default = r["basis"]
        if not layer.Export(tmp):
            raise OSError("'%s': OpenUSD cannot write the layer" % path)

    _write_atomically(path, write)


def ingest(stage, output, *, force=False, **options):
    """The textures of `stage` (textures()) converted into the folder `output` as
    spectralize.ingest() converts files: each with the colour space and mode the stage decides
    (a data map skipped, a file the stage says nothing of decided by its own tags and the
    config), incrementally, with ingest's manifest; its lights (lights()) as spectra, one JSON
    file each under output/lights/; and output/spectral.usda, a layer with the stage as its
    sublayer that only adds attributes in the spectralize: namespace: each converted texture's
    spectral file (spectralize:file, or spectralize:files for UDIM tiles), its mode and colour
    space, each light's spectralize:wavelengths, spectralize:values and spectralize:basis (the
    original files are never written). options: ingest's (config, wavelengths, model, ...); a
    setting the stage decides for a file (colorspace, mode) is the stage's. Returns ingest's
    summary with "textures" (the stage's decisions with their prim paths and reasons),
    "asset_failures" (textures whose file is missing), "lights" and "light_failures", and
    "layer". Cost: composing the stage, then ingest's, one spectrum per light."""
    import spectralize

    Sdf, Usd, _, _ = _pxr()
    opened = _open(stage)
    root_layer = opened.GetRootLayer().realPath
    if not root_layer:
        raise ValueError("ingest(): the stage has no file (an in-memory stage): save it first")
    records = textures(opened)
    lines = [list_line(r) for r in records]
    with tempfile.TemporaryDirectory(prefix="spectralize-usd-") as folder:
        listing = os.path.join(folder, "inputs.jsonl")
        with open(listing, "w", encoding="utf-8") as f:
            for line in lines:
                if line:
                    f.write(json.dumps(line) + "\n")
        summary = spectralize.ingest([], output, inputs_from=listing, force=force, **options)
    # What each file became, from ingest's own manifest.
    manifest = os.path.join(output, "spectralize-ingest.jsonl")
    done = {}
    with open(manifest, encoding="utf-8") as f:
        for line in f:
            m = json.loads(line)
            if m.get("status") in ("converted", "up_to_date") and "output" in m:
                done[os.path.abspath(m["input"])] = m
    textures_done = {}
    for r in records:
        m = done.get(os.path.abspath(r["input"])) if "input" in r else None
        if m:
            r["output"] = os.path.abspath(m["output"])
            textures_done.setdefault(r["prim"], []).append(
                {"output": r["output"], "mode": m.get("mode"), "colorspace": m.get("colorspace")})
    light_records = lights(opened, **{k: v for k, v in options.items() if k in LIGHT_OPTIONS})
    light_folder = os.path.join(output, "lights")
    for r in light_records:
        if "values" not in r:
            continue
        os.makedirs(light_folder, exist_ok=True)
        r["file"] = os.path.join(light_folder, _light_file_name(r["prim"]) + ".json")
        payload = {k: v for k, v in r.items() if k not in ("wavelengths", "values", "file")}
        payload["wavelengths_nm"] = [float(v) for v in r["wavelengths"]]
        payload["values"] = [float(v) for v in r["values"]]

        def write(tmp, payload=payload):
            with open(tmp, "w", encoding="utf-8") as f:
                json.dump(payload, f, indent=1)
                f.write("\n")

        _write_atomically(r["file"], write)
    layer = os.path.join(output, "spectral.usda")
    _override_layer(layer, root_layer, textures_done, light_records)
    summary["textures"] = records
    summary["asset_failures"] = [r for r in records if "failure" in r]
    summary["lights"] = light_records
    summary["light_failures"] = [r for r in light_records if "failure" in r]
    summary["layer"] = layer
    return summary


# The CIE D-series illuminant at the white of a space's primaries (the interop ID's middle
# part): D65 for the D65 spaces; the ACES white is no D-series white, D60 is the nearest.
D_SERIES_WHITE = {"rec709": "D65", "rec2020": "D65", "p3d65": "D65", "adobergb": "D65",
                  "ciexyzd65": "D65", "ap1": "D60", "ap0": "D60"}


def lights(stage, **options):
    """The emission spectrum of every UsdLux light of `stage` (a path or a Usd.Stage), as UsdLux
    asks: inputs:color (in the UsdColorSpaceAPI space in force at the light, else
    lin_rec709_scene) times inputs:intensity times 2^inputs:exposure, with the CIE D-series
    illuminant at the space's white as the emission basis (spectralize.spectra(), mode
    emission): white (1, 1, 1) is that illuminant itself and every colour is reproduced
    exactly, white-balanced to it (D65 for the D65 spaces; D60 for ACES, whose white is no
    D-series white: the record says so). options:
    spectra()'s (wavelengths, model, config, ...). Each record: "prim", "type", "colorspace",
    "colorspace_reason", "color", "scale", "basis", "basis_reason", "wavelengths", "values"
    (NumPy arrays); a light that cannot be made has "failure" instead (a negative colour, a
    colour temperature, a space whose white no D-series illuminant is, a space the config has
    no space for). An option spectra() refuses raises for the first light. Cost: composing the
    stage, one spectrum per light."""
    import numpy as np
    import spectralize

    _, Usd, UsdLux, _ = _pxr()
    stage = _open(stage)
    out = []
    for prim in stage.Traverse(Usd.TraverseInstanceProxies()):
        if not prim.HasAPI(UsdLux.LightAPI):
            continue
        light = UsdLux.LightAPI(prim)
        r = {"prim": str(prim.GetPath()), "type": str(prim.GetTypeName())}
        r["colorspace"], r["colorspace_reason"] = _space_in_force(
            prim, "lin_rec709_scene", "the stage declares none: OpenUSD's default, lin_rec709_scene")
        colour = light.GetColorAttr().Get()
        r["color"] = [float(c) for c in (colour if colour is not None else (1.0, 1.0, 1.0))]
        intensity = light.GetIntensityAttr().Get()
        exposure = light.GetExposureAttr().Get()
        r["scale"] = float(1.0 if intensity is None else intensity) * 2.0 ** float(
            0.0 if exposure is None else exposure)
        parts = r["colorspace"].split("_")
        r["basis"] = D_SERIES_WHITE.get(parts[1]) if len(parts) == 3 else None
        failure = None
        if light.GetEnableColorTemperatureAttr().Get():
            failure = "inputs:enableColorTemperature: a colour temperature is not made yet"
        elif min(r["color"]) < 0 or r["scale"] < 0:
            failure = "a negative colour or intensity: no light has it"
        elif r["basis"] is None:
            failure = "colour space '%s': no CIE D-series illuminant is known at its white" % (
                r["colorspace"])
        if failure:
            r["failure"] = "<%s>: %s" % (r["prim"], failure)
            out.append(r)
            continue
        r["basis_reason"] = ("the D-series illuminant at the space's white" if r["basis"] == "D65"
                             else "the ACES white is no D-series white: D60, the nearest "
                                  "(colours are white-balanced to it: white light is D60)")
        rgb = np.asarray(r["color"], dtype=np.float64) * r["scale"]
        try:
            r["wavelengths"], r["values"] = spectralize.spectra(
                rgb, colorspace=r["colorspace"], mode="emission", emission_basis=r["basis"],
                **options)
        except ValueError as e:  # a space the config lacks: this light's failure
            r["failure"] = "<%s>: %s" % (r["prim"], str(e).split(". Valid names")[0])
        out.append(r)
    return out
