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
    declared, declarer = _declared_space(shader_prim)
    if word == "raw":
        d["colorspace"], d["colorspace_reason"] = "data", where + ".inputs:sourceColorSpace 'raw'"
    elif word == "sRGB":
        d["colorspace"] = "srgb_rec709_scene"
        d["colorspace_reason"] = where + ".inputs:sourceColorSpace 'sRGB'"
    elif declared:
        d["colorspace"] = "data" if declared in DATA_SPACES else declared
        d["colorspace_reason"] = "colorSpace:name '%s' of <%s> (UsdColorSpaceAPI)" % (
            declared, declarer.GetPath())
    else:
        d["colorspace"] = None
        d["colorspace_reason"] = "the stage declares none: the file's own tags and the config's rules"
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
    declared, declarer = _declared_space(light_prim)
    d = {"feeds": [], "mode": "emission",
         "mode_reason": "the texture of DomeLight <%s>" % light_prim.GetPath()}
    if declared:
        d["colorspace"] = "data" if declared in DATA_SPACES else declared
        d["colorspace_reason"] = "colorSpace:name '%s' of <%s> (UsdColorSpaceAPI)" % (
            declared, declarer.GetPath())
    else:
        d["colorspace"] = None
        d["colorspace_reason"] = "the stage declares none: the file's own tags and the config's rules"
    return d


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


def ingest(stage, output, *, force=False, **options):
    """The textures of `stage` (textures()) converted into the folder `output` as
    spectralize.ingest() converts files: each with the colour space and mode the stage decides
    (a data map skipped, a file the stage says nothing of decided by its own tags and the
    config), incrementally, with ingest's manifest. options: ingest's (config, wavelengths,
    model, ...); a setting the stage decides for a file (colorspace, mode) is the stage's.
    Returns ingest's summary with "textures" (the records of textures(), the stage's
    decisions with their prim paths and reasons) and "asset_failures" (those whose file is
    missing). Cost: composing the stage, then ingest's."""
    import spectralize

    records = textures(stage)
    lines = [list_line(r) for r in records]
    with tempfile.TemporaryDirectory(prefix="spectralize-usd-") as folder:
        listing = os.path.join(folder, "inputs.jsonl")
        with open(listing, "w", encoding="utf-8") as f:
            for line in lines:
                if line:
                    f.write(json.dumps(line) + "\n")
        summary = spectralize.ingest([], output, inputs_from=listing, force=force, **options)
    summary["textures"] = records
    summary["asset_failures"] = [r for r in records if "failure" in r]
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
        declared, declarer = _declared_space(prim)
        if declared:
            r["colorspace"] = declared
            r["colorspace_reason"] = "colorSpace:name '%s' of <%s> (UsdColorSpaceAPI)" % (
                declared, declarer.GetPath())
        else:
            r["colorspace"] = "lin_rec709_scene"
            r["colorspace_reason"] = "the stage declares none: OpenUSD's default, lin_rec709_scene"
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
