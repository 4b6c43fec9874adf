"""spectralize.usd: the textures of an OpenUSD stage, decided as a TD would (docs/guide/usd.md).

textures(stage) opens a stage (every layer, reference and payload composed) and returns each
texture file it uses: the files of UsdUVTexture shaders and MaterialX image nodes (UDIM tiles
expanded; every file of a texture sequence) and of lights (a DomeLight's, a RectLight's), with
the colour space the stage declares for them and what they feed:

- colour space: UsdUVTexture's inputs:sourceColorSpace ("raw": data; "sRGB":
  srgb_rec709_scene), else the file input's own colorSpace metadata (MaterialX's
  colorspace), else the UsdColorSpaceAPI space in force at the shader (the nearest
  ancestor, the prim included, that applies the API and authors colorSpace:name; "raw",
  "identity" and "data" are data); where the stage declares nothing, None: the file's own tags
  and the config's file rules decide, as for any file;
- light, surface or data: a light's texture (DomeLight, RectLight) and an emissive colour
  input (emissiveColor, emission_color) are light; a surface colour input (diffuseColor, base_color,
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
import posixpath
import re
import tempfile

__all__ = ["textures", "list_line", "ingest", "lights"]

# What a texture feeds, by the consumer input's name (UsdPreviewSurface, MaterialX
# standard_surface and OpenPBR spellings).
SURFACE_COLOUR_INPUTS = {
    "diffuseColor", "specularColor", "base_color", "specular_color", "coat_color",
    "sheen_color", "subsurface_color", "transmission_color", "base_color_map", "fuzz_color",
}
EMISSIVE_COLOUR_INPUTS = {"emissiveColor", "emission_color", "emissive"}
# Surface (and displacement) shaders: what a texture feeds there decides what it is; any
# other shader with an input of a name not known passes the texture on (a multiply, a mix).
SURFACE_SHADER = re.compile(r"UsdPreviewSurface|ND_\w+_surfaceshader(_\w+)?|"
                            r"ND_displacement_\w+")
# The shaders that read a texture file (inputs:file): UsdPreviewSurface's, as itself or as
# MaterialX's node for it, and MaterialX's image nodes (image, tiledimage, hextiledimage,
# gltf_image, gltf_colorimage, of any output type).
TEXTURE_SHADER = re.compile(r"(ND_)?UsdUVTexture(_\w+)?|ND_(tiled|hextiled)?image_\w+|"
                            r"ND_gltf_(color)?image_\w+")
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
        opened = _quietly(lambda: Usd.Stage.Open(path, Usd.Stage.LoadAll))
    except Exception as e:  # pxr raises Tf errors as RuntimeError and friends
        raise OSError("USD stage '%s': %s" % (path, _tf_message(str(e)))) from e
    if not opened:
        raise OSError("USD stage '%s': OpenUSD cannot open it" % path)
    return opened


def _quietly(run):
    """run() with OpenUSD's own warnings (printed on stderr by its diagnostics) held back:
    what they say of the stage is reported as its failures (GetCompositionErrors)."""
    import sys
    sys.stderr.flush()
    saved, null = os.dup(2), os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(null, 2)
        return run()
    finally:
        os.dup2(saved, 2)
        os.close(saved)
        os.close(null)


def _tf_message(text):
    """OpenUSD's own words of a Tf error, without where in OpenUSD's sources it was raised."""
    text = text.strip()
    m = re.match(r"^Error in '[^']*' at line \d+ in file [^:]* : '(.*)'$", text, re.S)
    return (m.group(1) if m else text).strip()


def _space_in_force(prim, undeclared, undeclared_reason, attr=None):
    """The colour space the stage declares for `prim` (the colorSpace metadata of its attribute
    `attr` itself where given and authored, else UsdColorSpaceAPI; "data" for a data space)
    and why; (`undeclared`, `undeclared_reason`) where it declares none."""
    if attr and attr.HasColorSpace():
        declared = str(attr.GetColorSpace())
        return ("data" if declared in DATA_SPACES else declared,
                "colorSpace '%s' of <%s>.%s" % (declared, attr.GetPrim().GetPath(),
                                                 attr.GetName()))
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


# Inputs that say what a texture is; a shader input of another name (a multiply, a
# transform) passes the texture on, so what its outputs feed decides.
DATA_INPUTS = {"normal", "roughness", "metallic", "opacity", "opacityThreshold", "displacement",
               "occlusion", "clearcoat", "clearcoatRoughness", "ior", "specular_roughness",
               "metalness", "coat", "coat_roughness", "transmission", "bump", "height"}


def _consumers(stage):
    """For each prim whose outputs shader inputs read: the inputs that decide what it is, as
    (consumer prim, input name), followed through NodeGraph and Material outputs and interface
    inputs and through shaders that pass a texture on."""
    _, Usd, _, UsdShade = _pxr()
    edges = {}  # (source prim path, its port name) -> [(consumer prim, port name, is output)]
    for prim in stage.Traverse(Usd.TraverseInstanceProxies()):
        connectable = UsdShade.ConnectableAPI(prim)
        if not connectable:
            continue
        ports = [(i, False) for i in connectable.GetInputs()] + \
                [(o, True) for o in connectable.GetOutputs()]
        for port, is_output in ports:
            for source in port.GetConnectedSources()[0]:
                key = (source.source.GetPrim().GetPath(), str(source.sourceName))
                edges.setdefault(key, []).append((prim, port.GetBaseName(), is_output))
    by_prim = {}
    for (path, _), consumers in edges.items():
        by_prim.setdefault(path, []).extend(consumers)

    def deciding(path):
        out, seen, todo = [], set(), list(by_prim.get(path, []))
        while todo:
            prim, name, is_output = todo.pop(0)
            if (prim.GetPath(), name, is_output) in seen:
                continue
            seen.add((prim.GetPath(), name, is_output))
            if not prim.IsA(UsdShade.Shader):  # a graph's or material's port: what it feeds
                todo += edges.get((prim.GetPath(), name), [])
                continue
            shader_id = UsdShade.Shader(prim).GetShaderId()
            passes_on = (not is_output and not SURFACE_SHADER.fullmatch(shader_id or "") and
                         name not in SURFACE_COLOUR_INPUTS | EMISSIVE_COLOUR_INPUTS | DATA_INPUTS)
            onward = by_prim.get(prim.GetPath(), []) if passes_on else []
            if onward:
                todo += onward
            elif not is_output:
                out.append((prim, name))
        return out

    return {path: deciding(path) for path in by_prim}


def _authoring_spec(attr):
    """The strongest spec of `attr` that gives it a value (a default or time samples)."""
    for spec in attr.GetPropertyStack():
        if spec.default is not None or spec.layer.GetNumTimeSamplesForPath(spec.path):
            return spec
    return None


def _anchored(attr, path):
    """An authored asset path relative to the layer that authors it (OpenUSD's default
    resolver anchors the same way)."""
    spec = _authoring_spec(attr)
    return _anchored_to_layer(spec.layer, path) if spec else path


def _anchored_to_layer(layer, path):
    """`path` relative to `layer`: beside it on disk, or in the .usdz package it is in
    ("<package>[<its path there>]")."""
    if os.path.isabs(path) or not layer.realPath:
        return path
    package, inner = _package_of(layer.realPath)
    if package:
        return "%s[%s]" % (package, _inside(inner, path))
    return os.path.normpath(os.path.join(os.path.dirname(layer.realPath), path))


def _inside(inner, path):
    """`path` relative to a layer at `inner` in a package (a package in it: nested)."""
    nested, deeper = _package_of(inner)
    if nested:
        return "%s[%s]" % (nested, _inside(deeper, path))
    return posixpath.normpath(posixpath.join(posixpath.dirname(inner), path))


def _asset_values(attr):
    """[(times, asset)]: each distinct asset path the attribute takes, with the times it takes
    it at ("default" for its default), in order of first use; [([], default)] for an attribute
    that is not animated. Cost: O(time samples)."""
    samples = attr.GetTimeSamples()
    if not samples:
        return [([], attr.Get())]
    _, Usd, _, _ = _pxr()
    spec = _authoring_spec(attr)
    timed = [("default", attr.Get())] if spec and spec.default is not None else []
    timed += [(t, attr.Get(Usd.TimeCode(t))) for t in samples]
    out = {}
    for t, value in timed:
        out.setdefault(value.path if value else "", (value, []))[1].append(t)
    return [(times, value) for value, times in out.values()]


def _resolved(attr, asset):
    """The files an asset path names: its resolved path, or the UDIM tiles (1001-1999) that
    exist where the layer that authors it says: beside it on disk, or inside the .usdz
    package it is in ("<package>[<file>]", as OpenUSD names a packaged file)."""
    if UDIM not in asset.path:
        return [asset.resolvedPath] if asset.resolvedPath else []
    anchored = _anchored(attr, asset.path)
    package, inner = _packaged(anchored)
    if package:
        if "[" in inner:  # a package inside a package
            return []
        Sdf, _, _, _ = _pxr()
        pattern = re.escape(inner).replace(re.escape(UDIM), r"(1\d\d\d)")
        names = Sdf.ZipFile.Open(package).GetFileNames()
        return ["%s[%s]" % (package, n) for n in sorted(names) if re.fullmatch(pattern, n)]
    pattern = re.escape(anchored).replace(re.escape(UDIM), r"(1\d\d\d)")
    tiles = [p for p in glob.glob(anchored.replace(UDIM, "1[0-9][0-9][0-9]"))
             if re.fullmatch(pattern, p)]
    return sorted(tiles)


def _packaged(path):
    """(package, path inside it) for a packaged file ("a.usdz[tex/b.png]"); ("", "") for a
    file on disk."""
    if path.endswith("]") and "[" in path:
        package, inner = path[:-1].split("[", 1)
        return package, inner
    return "", ""


def _package_of(layer_path):
    """(package, the layer's path inside it) for a layer in a .usdz package ("a.usdz[b.usda]",
    or the package itself, whose first file is its layer: inner ""); ("", "") otherwise."""
    if layer_path.lower().endswith(".usdz"):
        return layer_path, ""
    return _packaged(layer_path)


def _texture_records(prim, named, attr, decide):
    """The records of the file(s) the attribute `named` of `prim` names, its value given by
    `attr` (itself, or the interface input it is connected to)."""
    common = {"prim": str(prim.GetPath()), "attribute": named.GetName()}
    if attr.GetPath() != named.GetPath():
        common["value_from"] = str(attr.GetPath())
    # A value authored inside a variant of the stage's own layers: the layer's opinion goes
    # into the same variant, so that it holds only while that variant is selected.
    spec = _authoring_spec(attr)
    if spec and spec.path.ContainsPrimVariantSelection():
        stack = {layer.identifier for layer in prim.GetStage().GetLayerStack()}
        if spec.layer.identifier in stack and attr.GetPath() == named.GetPath():
            common["layer_path"] = str(spec.path.GetPrimPath())
        else:
            common["variant_note"] = (
                "its file comes from variant %s of a layer the stage references: the "
                "layer points at it whatever variant is selected" % spec.path.GetPrimPath())
    common.update(decide())
    out = []
    # An animated file (a texture sequence): each file it names, with the times it is used.
    for times, value in _asset_values(attr):
        record = dict(common, asset=value.path if value else "")
        if times:
            record["times"] = times
        out += _asset_records(record, attr, value)
    return out


def _asset_records(record, attr, value):
    """The records of the files one asset path names (UDIM tiles: several), or its failure."""
    files = _resolved(attr, value) if value else []
    if not files:
        failed = dict(record)
        failed["failure"] = "%s.%s: %s" % (
            record["prim"], record["attribute"],
            "asset '%s' not found" % record["asset"] if record["asset"] else "no asset authored")
        if record.get("times"):
            failed["failure"] += " (%s)" % _times_said(record["times"])
        anchored = _anchored(attr, value.path) if value and value.path else ""
        package, inner = _packaged(anchored)
        if UDIM in anchored and "[" in inner:
            failed["failure"] = "%s.%s: UDIM tiles inside a package inside a package are not " \
                                "expanded" % (record["prim"], record["attribute"])
        elif UDIM in anchored and package:
            failed["failure"] = "%s.%s: no UDIM tile '%s' inside the package '%s'" % (
                record["prim"], record["attribute"], value.path, package)
        elif anchored:
            failed["missing"] = anchored
        return [failed]
    out = []
    for f in files:
        r = dict(record)
        r["input"] = f
        out.append(r)
    return out


def _times_said(times):
    """"at times 1, 2" / "as its default and at time 3": when an animated value is used."""
    timed = ["%g" % t for t in times if t != "default"]
    said = "at time%s %s" % ("s" if len(timed) > 1 else "", ", ".join(timed)) if timed else ""
    if "default" in times:
        return "as its default" + (" and " + said if said else "")
    return said


def _producing(inp):
    """The attribute that gives a shader input its value: its own, or through its connections
    (a Material's interface input)."""
    attrs = inp.GetValueProducingAttributes()
    return attrs[0] if attrs else inp.GetAttr()


def _feeds_reason(what, feeds, deciding):
    """"feeds a surface colour: <S>.inputs:diffuseColor (also <S>.inputs:opacity)"."""
    said = [f for f in feeds if f.rsplit(":", 1)[-1] in deciding]
    also = [f for f in feeds if f not in said]
    return "feeds %s: %s%s" % (what, ", ".join(said),
                               " (also %s)" % ", ".join(also) if also else "")


def _uv_texture_decision(shader_prim, fed, file_attr):
    _, _, _, UsdShade = _pxr()
    shader = UsdShade.Shader(shader_prim)
    where = "<%s>" % shader_prim.GetPath()
    feeds = ["<%s>.inputs:%s" % (p.GetPath(), name) for p, name in fed.get(shader_prim.GetPath(), [])]
    names = {name for _, name in fed.get(shader_prim.GetPath(), [])}
    source = shader.GetInput("sourceColorSpace")
    value = _producing(source).Get() if source else None
    word = str(value) if value else "auto"
    d = {"feeds": feeds}
    if word == "raw":
        d["colorspace"], d["colorspace_reason"] = "data", where + ".inputs:sourceColorSpace 'raw'"
    elif word == "sRGB":
        d["colorspace"] = "srgb_rec709_scene"
        d["colorspace_reason"] = where + ".inputs:sourceColorSpace 'sRGB'"
    else:  # the asset attribute's own colorSpace metadata, else UsdColorSpaceAPI
        d["colorspace"], d["colorspace_reason"] = _space_in_force(shader_prim, None,
                                                                  NO_DECLARATION, file_attr)
    if d["colorspace"] == "data":
        d["mode"], d["mode_reason"] = "data", "its colour space is data (%s)" % d["colorspace_reason"]
    elif names & EMISSIVE_COLOUR_INPUTS:
        d["mode"], d["mode_reason"] = "emission", _feeds_reason(
            "an emissive colour", feeds, EMISSIVE_COLOUR_INPUTS)
    elif names & SURFACE_COLOUR_INPUTS:
        d["mode"], d["mode_reason"] = "reflectance", _feeds_reason(
            "a surface colour", feeds, SURFACE_COLOUR_INPUTS)
    elif names:
        d["mode"], d["mode_reason"] = "data", "feeds no colour: " + ", ".join(feeds)
    else:
        d["mode"], d["mode_reason"] = None, "feeds nothing: the file's own decision"
    return d


def _light_texture_decision(light_prim, file_attr):
    colorspace, reason = _space_in_force(light_prim, None, NO_DECLARATION, file_attr)
    return {"feeds": [], "mode": "emission",
            "mode_reason": "the texture of %s <%s>" % (light_prim.GetTypeName(),
                                                       light_prim.GetPath()),
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
            if not TEXTURE_SHADER.fullmatch(shader.GetShaderId() or ""):
                continue
            file_input = shader.GetInput("file")
            if not file_input:
                continue
            attr = _producing(file_input)
            out += _texture_records(prim, file_input.GetAttr(), attr,
                                    lambda: _uv_texture_decision(prim, fed, attr))
        elif prim.HasAPI(UsdLux.LightAPI):  # a DomeLight's sky, a RectLight's picture
            attr = prim.GetAttribute("inputs:texture:file")
            if attr and (attr.HasAuthoredValue() or attr.GetNumTimeSamples()):
                out += _texture_records(prim, attr, attr,
                                        lambda: _light_texture_decision(prim, attr))
    return out


def _origin(record):
    """Where a record comes from, as ingest records it in the manifest ("origin")."""
    o = {"where": "<%s>.%s%s" % (record["prim"], record["attribute"],
                                 " " + _times_said(record["times"]) if record.get("times") else ""),
         "prim": record["prim"],
         "attribute": record["attribute"], "asset": record["asset"],
         "feeds": record.get("feeds", [])}
    for key in ("value_from", "packaged", "times"):
        if record.get(key):
            o[key] = record[key]
    # The reasons of what the line gives (ingest records them instead of "--colorspace").
    if record.get("mode") == "data":
        o["colorspace_reason"] = (record["colorspace_reason"] if record.get("colorspace") == "data"
                                  else record["mode_reason"])
    elif record.get("colorspace"):
        o["colorspace_reason"] = record["colorspace_reason"]
    if record.get("mode") in ("reflectance", "emission"):
        o["mode_reason"] = record["mode_reason"]
    return o


# Where a file outside the stage's folder is mirrored in the output: its absolute path under
# this folder, so two libraries' albedo.png stay apart.
EXTERNAL_FOLDER = "external"


def list_line(record, source=None, stage_file=None):
    """A record as a line of `ingest --inputs-from` (a JSON object: the file, the settings the
    stage decided, data as the config's data role, and "origin": the prim, attribute, inputs
    it feeds and the reasons, which ingest records in the manifest). With `source` (a folder,
    the stage's), a file inside it is given relative to it, so the output mirrors its place
    there, and a file outside it is mirrored under external/ by its absolute path. A record
    whose file is missing becomes a line for the missing file, which ingest fails naming its
    prim; one with no file at all, with `stage_file`, a failure line for the stage. Cost: O(1)."""
    path = record.get("input") or record.get("missing")
    if not path:
        if record.get("failure") and stage_file:
            return {"input": stage_file, "failure": record["failure"].split(": ", 1)[-1],
                    "origin": _origin(record)}
        return None
    line = {"input": path}
    source = record.get("package_folder", source)  # a packaged file mirrors its package's tree
    if source:
        rel = os.path.relpath(path, source)
        if not rel.startswith(".."):
            line = {"input": rel, "source": os.path.abspath(source)}
        else:
            line["as"] = os.path.join(EXTERNAL_FOLDER, os.path.abspath(path).lstrip(os.sep))
    if record.get("mode") == "data":
        line["colorspace"] = "data"
    else:
        if record.get("colorspace"):
            line["colorspace"] = record["colorspace"]
        if record.get("mode"):
            line["mode"] = record["mode"]
    line["origin"] = _origin(record)
    return line


PACKAGE_FOLDER = "usdz-contents"


def _unpack(records, output, reads):
    """Each texture inside a .usdz package copied out once into output/usdz-contents/
    <package>/ (kept, with the package's time, so a rerun finds it and its output up to date);
    the record's "input" becomes that file, "packaged" the path inside the package."""
    from pxr import Ar
    for r in records:
        path = r.get("input", "")
        if not (path.endswith("]") and "[" in path):
            continue
        package, inner = path[:-1].split("[", 1)
        stem = os.path.splitext(os.path.basename(package))[0]
        target = os.path.join(output, PACKAGE_FOLDER, stem, os.path.normpath(inner))
        _refuse_to_replace(target, reads)
        st = os.stat(package)
        done = os.path.isfile(target) and os.stat(target).st_mtime_ns == st.st_mtime_ns
        if not done:
            asset = Ar.GetResolver().OpenAsset(Ar.ResolvedPath(path))
            if not asset:
                r.pop("input")
                r["failure"] = "%s.%s: '%s' cannot be read from its package" % (
                    r["prim"], r["attribute"], path)
                continue
            os.makedirs(os.path.dirname(target), exist_ok=True)
            _write_atomically(target, bytes(asset.GetBuffer()), (st.st_atime_ns, st.st_mtime_ns))
        r["packaged"], r["input"] = path, target
        r["package_folder"] = os.path.join(output, PACKAGE_FOLDER, stem)


# The options of ingest() that shape a light's spectrum too (spectra() takes them).
LIGHT_OPTIONS = ("wavelengths", "observer", "model", "filter", "curvature", "config")


def _write_atomically(path, data, times=None):
    """Writes the bytes `data` to `path` as the tool writes every file: an exclusive temporary
    beside it (".NAME.spectralize-XXXXXX.tmp", locked while written, so a rerun's sweep
    removes what a killed run left and never a live one's), flushed to disk, renamed when
    complete; `times` (atime, mtime in ns) set before the rename."""
    import fcntl
    import secrets
    import string
    folder = os.path.dirname(os.path.abspath(path))
    _sweep(folder)
    letters = string.ascii_letters + string.digits
    while True:
        tmp = os.path.join(folder, ".%s.spectralize-%s.tmp" % (
            os.path.basename(path), "".join(secrets.choice(letters) for _ in range(6))))
        try:
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_CLOEXEC, 0o644)
            break
        except FileExistsError:
            continue
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        view = memoryview(data)
        while view:
            view = view[os.write(fd, view):]
        os.fsync(fd)
        if times:
            os.utime(fd, ns=times)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise
    finally:
        os.close(fd)


TEMPORARY = re.compile(r"^\..+\.spectralize-[A-Za-z0-9]{6}\.tmp$")
_swept = set()


def _sweep(folder):
    """Removes, once per folder and process, the temporaries a killed run left there (every
    writer's, the tool's included: a live one holds its lock and stays)."""
    import fcntl
    if folder in _swept or not os.path.isdir(folder):
        return
    _swept.add(folder)
    for name in os.listdir(folder):
        path = os.path.join(folder, name)
        if not TEMPORARY.match(name) or os.path.islink(path) or not os.path.isfile(path):
            continue
        try:
            fd = os.open(path, os.O_RDONLY | os.O_CLOEXEC)
        except OSError:
            continue
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            os.unlink(path)
        except OSError:
            pass
        finally:
            os.close(fd)


def _reads(opened, records=()):
    """Every file the stage's ingest reads: its layers, packages and textures (real paths)."""
    paths = {layer.realPath for layer in opened.GetUsedLayers() if layer.realPath}
    paths |= {r["input"] for r in records if r.get("input")}
    return {os.path.realpath(p.split("[", 1)[0]) for p in paths}


def _refuse_to_replace(path, reads):
    """OSError when writing `path` would replace a file the stage's ingest reads."""
    if os.path.realpath(path) in reads:
        raise OSError("'%s' is a file of the stage (a layer, package or texture): writing it "
                      "would replace it; choose another output folder" % path)


def _light_file_name(prim):
    # Prim names are identifiers (letters, digits, _): "." cannot be part of one.
    return prim.strip("/").replace("/", ".") or "root"


def _custom(spec, name, type_name):
    """A custom attribute `name` of type Sdf.ValueTypeNames.<type_name> on the prim spec."""
    Sdf, _, _, _ = _pxr()
    return Sdf.AttributeSpec(spec, name, getattr(Sdf.ValueTypeNames, type_name),
                             Sdf.VariabilityVarying, True)


def _override_layer(path, opened, textures_done, light_records):
    """spectral.usda: the original stage as a sublayer, and overs that only add attributes in
    the spectralize: namespace (docs/guide/files.md). Returns the prims it could not point at:
    those under an instance, where OpenUSD ignores a layer's opinions."""
    Sdf, _, _, _ = _pxr()
    from pxr import Vt
    folder = os.path.dirname(os.path.abspath(path))
    skipped = []

    def under_instance(prim_path):
        prim = opened.GetPrimAtPath(Sdf.Path(prim_path).StripAllVariantSelections())
        if prim and prim.IsInstanceProxy():
            skipped.append(prim_path)
            return True
        return False

    def text():
        layer = Sdf.Layer.CreateAnonymous(".usda")
        layer.subLayerPaths.append(os.path.relpath(opened.GetRootLayer().realPath, folder))
        for prim, entries in textures_done.items():
            if under_instance(prim):
                continue
            spec = Sdf.CreatePrimInLayer(layer, prim)
            spec.specifier = Sdf.SpecifierOver
            # Per asset path the prim's file takes (several for an animated file), its outputs.
            by_asset = {}
            for e in entries:
                by_asset.setdefault(e["asset"], (e["times"], []))[1].append(
                    os.path.relpath(e["output"], folder))
            tiles = any(len(outputs) > 1 or UDIM in asset
                        for asset, (_, outputs) in by_asset.items())
            attr = _custom(spec, "spectralize:files" if tiles else "spectralize:file",
                           "AssetArray" if tiles else "Asset")
            for times, outputs in by_asset.values():
                value = Sdf.AssetPathArray(outputs) if tiles else Sdf.AssetPath(outputs[0])
                for t in times or ["default"]:
                    if t == "default":
                        attr.default = value
                    else:  # a texture sequence: the spectral file of each time's file
                        layer.SetTimeSample(attr.path, t, value)
            for key in ("mode", "colorspace"):
                a = _custom(spec, "spectralize:" + key, "String")
                a.default = str(entries[0][key])
        for r in light_records:
            if "values" not in r or under_instance(r["prim"]):
                continue
            spec = Sdf.CreatePrimInLayer(layer, r["prim"])
            spec.specifier = Sdf.SpecifierOver
            a = _custom(spec, "spectralize:wavelengths", "FloatArray")
            a.default = [float(v) for v in r["wavelengths"]]
            values = _custom(spec, "spectralize:values", "FloatArray")
            basis = _custom(spec, "spectralize:basis", "String")
            if "times" not in r:
                values.default = [float(v) for v in r["values"]]
                basis.default = r["basis"]
            else:  # animated: time samples, as the light's inputs have them
                for t, row, sample in zip(r["times"], r["values"], r["samples"]):
                    layer.SetTimeSample(values.path, t, Vt.FloatArray([float(v) for v in row]))
                    layer.SetTimeSample(basis.path, t, sample["basis"])
        return layer.ExportToString()

    _write_atomically(path, text().encode("utf-8"))
    return ["<%s>: under an instance, where a layer's opinions are ignored: its spectra are not "
            "in the layer" % p for p in skipped]


def _decision_tag(record):
    tag = "-".join([record.get("mode") or "auto", record.get("colorspace") or "own"])
    return re.sub(r"[^A-Za-z0-9_.-]", "_", tag)


def _stage_lines(opened, output, options):
    """What the stage gives ingest: its texture records (packaged ones copied out under
    `output`), the list lines (relative to the stage's folder; one per file and decision, a
    file the stage declares differently in two places converted once per decision, under a
    tagged name; failure lines for what has no file, the layers the stage cannot compose and
    the lights that cannot be made), the light records (each made light written as
    output/lights/<prim>.json) and the conflicts said."""
    records = textures(opened)
    reads = _reads(opened, records)
    _refuse_to_replace(os.path.join(output, "spectral.usda"), reads)
    _unpack(records, output, reads)
    root = opened.GetRootLayer().realPath
    source = os.path.dirname(root)
    groups = {}
    for r in records:
        if r.get("input") or r.get("missing"):
            key = (r.get("colorspace"), r.get("mode"))
            groups.setdefault(r.get("input") or r["missing"], {}).setdefault(key, []).append(r)
    lines, conflicts = [], []
    for path, decisions in groups.items():
        if len(decisions) > 1:
            said = "; ".join("%s: %s" % (", ".join("<%s>" % r["prim"] for r in rs),
                                         "%s (%s)" % (k[1] or "its own mode", k[0] or "its own space"))
                             for k, rs in decisions.items())
            conflicts.append("'%s' is declared differently (%s): converted once per decision"
                             % (path, said))
        for rs in decisions.values():
            line = list_line(rs[0], source)
            line["origin"]["prims"] = [r["prim"] for r in rs]
            if len(decisions) > 1:
                line["origin"]["conflict"] = conflicts[-1]
                mirror = line.get("as") or line["input"]
                stem, ext = os.path.splitext(mirror)
                line["as"] = "%s.%s%s" % (stem, _decision_tag(rs[0]), ext)
            lines.append(line)
    for r in records:
        if not (r.get("input") or r.get("missing")):
            lines.append(list_line(r, source, stage_file=root))
    said = _colour_configuration_note(opened, options)
    if said:
        conflicts.append(said)
    for error in opened.GetCompositionErrors():
        lines.append({"input": root, "failure": _tf_message(str(error)),
                      "origin": {"where": "a layer of the stage"}})
    light_records = lights(opened, **{k: v for k, v in options.items() if k in LIGHT_OPTIONS})
    light_folder = os.path.join(output, "lights")
    for r in light_records:
        if "failure" in r:
            lines.append({"input": root, "failure": r["failure"].split(">: ", 1)[-1],
                          "origin": {"where": "<%s>" % r["prim"], "prim": r["prim"]}})
            continue
        if "values" not in r:  # a portal: no emission of its own
            continue
        os.makedirs(light_folder, exist_ok=True)
        r["file"] = os.path.join(light_folder, _light_file_name(r["prim"]) + ".json")
        payload = {k: v for k, v in r.items() if k not in ("wavelengths", "values", "file")}
        payload["wavelengths_nm"] = [float(v) for v in r["wavelengths"]]
        payload["values"] = r["values"].tolist()  # one row per time for an animated light
        _write_atomically(r["file"], (json.dumps(payload, indent=1) + "\n").encode("utf-8"))
    return records, lines, light_records, conflicts


def _colour_configuration_note(opened, options):
    """What to say when the stage names an OCIO config (its colorConfiguration metadata) other
    than the one its colour-space names are read in (`config`, else $OCIO, else the built-in
    default): the names may mean other spaces there. None when they are the same file."""
    named = opened.GetColorConfiguration()
    if not named or not named.path:
        return None
    stage_config = named.resolvedPath or _anchored_to_layer(opened.GetRootLayer(), named.path)
    in_use = options.get("config") or os.environ.get("OCIO") or ""
    try:
        if in_use and os.path.samefile(stage_config, in_use):
            return None
    except OSError:
        pass
    return ("the stage names its colour configuration '%s' (colorConfiguration); its colour "
            "space names are read in %s: give --config '%s' to read them in the stage's" % (
                named.path, "'%s'" % in_use if in_use else "the built-in default config",
                stage_config))


def _write_lines(path, lines):
    with open(path, "w", encoding="utf-8") as f:
        for line in lines:
            f.write(json.dumps(line) + "\n")


def _finish(opened, records, output, manifest, light_records):
    """After ingest: what each texture became (from the manifest's records of the stage's
    lines) and spectral.usda."""
    _refuse_to_replace(os.path.join(output, "spectral.usda"), _reads(opened, records))
    outputs = {}  # (prim, input) -> [(output, mode, colour space)]
    if os.path.isfile(manifest):
        with open(manifest, encoding="utf-8") as f:
            for line in f:
                m = json.loads(line)
                if m.get("status") not in ("converted", "up_to_date") or "output" not in m:
                    continue
                for prim in m.get("origin", {}).get("prims", []):
                    outputs.setdefault((prim, os.path.abspath(m["input"])), []).append(m)
    textures_done = {}
    for r in records:
        for m in outputs.get((r["prim"], os.path.abspath(r.get("input", ""))), []):
            r["output"] = os.path.abspath(m["output"])
            textures_done.setdefault(r.get("layer_path", r["prim"]), []).append(
                {"output": r["output"], "mode": m.get("mode"), "colorspace": m.get("colorspace"),
                 "asset": r["asset"], "times": r.get("times")})
    layer = os.path.join(output, "spectral.usda")
    skipped = _override_layer(layer, opened, textures_done, light_records)
    skipped += ["<%s>: %s" % (r["prim"], r["variant_note"]) for r in records
                if r.get("variant_note") and r.get("output")]
    return {"textures": records,
            "asset_failures": [r for r in records if "failure" in r],
            "lights": light_records,
            "light_failures": [r for r in light_records if "failure" in r],
            "layer_failures": [_tf_message(str(e)) for e in opened.GetCompositionErrors()],
            "not_in_layer": skipped,
            "layer": layer}


def ingest(stage, output, *, force=False, manifest=None, **options):
    """The textures of `stage` (textures()) converted into the folder `output` as
    spectralize.ingest() converts files: each with the colour space and mode the stage decides
    (a data map skipped, a file the stage says nothing of decided by its own tags and the
    config; a file it declares differently in two places converted once per decision, named
    with the decision), incrementally, with ingest's manifest, whose records carry "origin"
    (the prim, attribute, inputs fed, reasons, and "prims": every prim that uses it so) and
    "contradiction" where the file's own tag disagrees with the stage (the stage is followed);
    textures inside a .usdz are copied out once into output/usdz-contents/; its lights
    (lights()) as spectra, one JSON file each under output/lights/; and output/spectral.usda,
    a layer with the stage as its sublayer that only adds attributes in the spectralize:
    namespace: each converted texture's spectral file (spectralize:file, or spectralize:files
    for UDIM tiles), its mode and colour space, each light's spectralize:wavelengths,
    spectralize:values and spectralize:basis (the original files are never written: a layer
    that would replace one is refused, OSError). What the stage cannot give — a missing asset,
    a layer it cannot compose, a light that cannot be made — is a failed record of the
    manifest naming its prim, counted in "failed". options: ingest's (config, wavelengths,
    model, ...); a setting the stage decides for a file (colorspace, mode) is the stage's.
    Returns ingest's summary with "textures" (the stage's decisions), "asset_failures",
    "lights", "light_failures", "layer_failures", "conflicts" (files declared differently in
    two places; a colorConfiguration other than the config in use), "not_in_layer" (textures
    under an instance, which the layer cannot point at) and "layer"; a SpectralizeWarning names each
    conflict and each texture not in the layer. Cost: composing the stage, then ingest's, one
    spectrum per light."""
    import warnings

    import spectralize

    opened = _open(stage)
    if not opened.GetRootLayer().realPath:
        raise ValueError("ingest(): the stage has no file (an in-memory stage): save it first")
    os.makedirs(output, exist_ok=True)
    records, lines, light_records, conflicts = _stage_lines(opened, output, options)
    for said in conflicts:
        warnings.warn("spectralize.usd.ingest(): " + said, spectralize.SpectralizeWarning)
    with tempfile.TemporaryDirectory(prefix="spectralize-usd-") as folder:
        listing = os.path.join(folder, "inputs.jsonl")
        _write_lines(listing, lines)
        summary = spectralize.ingest([], output, inputs_from=listing, force=force,
                                     manifest=manifest, **options)
    summary.update(_finish(opened, records, output, summary["manifest"], light_records))
    summary["conflicts"] = conflicts
    for said in summary["not_in_layer"]:
        warnings.warn("spectralize.usd.ingest(): " + said, spectralize.SpectralizeWarning)
    return summary


def _main(argv):
    """The command line's half that needs OpenUSD (`spectralize ingest STAGE.usd`), one process
    per stage: "serve STAGE OUTPUT LIST OPTIONS VERBOSITY" writes the stage's list (and its
    lights), says "ready" on fd 3, then reads its command on fd 4 to its end: "finish\n"
    followed by the manifest's path writes spectral.usda from it; nothing (the tool ended the
    batch early) stops. OPTIONS: a JSON object of ingest's options; VERBOSITY 0 is -q. What
    fails is said on stderr. Returns the exit status: 0, 1 (something failed), 2 (another
    command), 3 (no OpenUSD)."""
    import sys
    try:
        _pxr()
    except ImportError as e:
        print(str(e), file=sys.stderr)
        return 3
    command, stage, output, listing, options = argv[0], argv[1], argv[2], argv[3], argv[4]
    if command != "serve":
        print("spectralize ERROR: spectralize.usd._main: unknown command '%s'" % command,
              file=sys.stderr)
        return 2
    quiet = len(argv) > 5 and argv[5] == "0"
    options = json.loads(options)
    try:
        opened = _open(stage)
        records, lines, light_records, conflicts = _stage_lines(opened, output, options)
        _write_lines(listing, lines)
        for said in conflicts:
            print("spectralize WARNING: '%s': %s" % (stage, said), file=sys.stderr)
        manifest = _serve_until_finish()
        if manifest is None:
            return 0
        done = _finish(opened, records, output, manifest, light_records)
    except (OSError, ValueError) as e:
        print("spectralize ERROR: " + str(e), file=sys.stderr)
        return 1
    except Exception as e:  # OpenUSD's own errors (Tf) and anything unforeseen: named, not a trace
        print("spectralize ERROR: '%s': %s: %s" % (stage, type(e).__name__, _tf_message(str(e))),
              file=sys.stderr)
        return 1
    for said in done["not_in_layer"]:
        print("spectralize WARNING: '%s': %s" % (stage, said), file=sys.stderr)
    if not quiet:
        made = sum(1 for r in done["lights"] if "values" in r)
        portals = sum(1 for r in done["lights"] if "not_made" in r)
        print("spectralize ingest: USD stage '%s': %d lights made, %d failed%s; layer '%s'" % (
            stage, made, len(done["light_failures"]),
            ", %d portal%s (no emission of its own)" % (portals, "s" if portals > 1 else "")
            if portals else "", done["layer"]), file=sys.stderr)
    return 0


def _serve_until_finish():
    """Says "ready" on fd 3 and waits for the tool's command on fd 4: the manifest's path, or
    None when the tool sends none (it closed the pipe: an interrupted or refused batch)."""
    import signal
    os.write(3, b"ready\n")
    os.close(3)
    # An interrupt is the tool's to handle: it ends the batch and closes the pipe.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    chunks = []
    while True:
        chunk = os.read(4, 65536)
        if not chunk:
            break
        chunks.append(chunk)
    os.close(4)
    command, _, manifest = b"".join(chunks).partition(b"\n")
    return os.fsdecode(manifest) if command == b"finish" and manifest else None


# The CIE D-series illuminant at the white of a space's primaries (the interop ID's middle
# part): D65 for the D65 spaces; the ACES white is no D-series white, D60 is the nearest.
D_SERIES_WHITE = {"rec709": "D65", "rec2020": "D65", "p3d65": "D65", "adobergb": "D65",
                  "ciexyzd65": "D65", "ap1": "D60", "ap0": "D60"}
# UsdLux's valid range of inputs:colorTemperature.
COLOR_TEMPERATURE_RANGE = (1000.0, 10000.0)
# The white every space of a config is converted through (docs/DESIGN.md §3: XYZ, D65, Y = 1).
D65_WHITE = (0.3127 / 0.3290, 1.0, 0.3583 / 0.3290)
XYZ_ROLE = "cie_xyz_d65_interchange"


class _Frame:
    """A light's colour space with the rendering illuminant `basis` as its white, as UsdLux
    reads colours: rgb() and xyz() convert between the space's RGB, white-balanced to the
    illuminant (docs/DESIGN.md §3: XYZ scaling), and CIE XYZ; each conversion goes through an
    exact spectrum (flat emission), so it is the config's own."""

    def __init__(self, colorspace, basis, options):
        import numpy as np
        import spectralize
        self.np, self.sp = np, spectralize
        self.space, self.options = colorspace, options
        self.to_rgb_options = {k: v for k, v in options.items() if k in ("config", "observer")}
        self.balance = self.emitted_xyz(D65_WHITE, basis) / np.asarray(D65_WHITE)

    def spectrum(self, rgb, colorspace, basis):
        return self.sp.spectra(self.np.asarray(rgb, dtype=self.np.float64), colorspace=colorspace,
                               mode="emission", emission_basis=basis, **self.options)

    def measured(self, wavelengths, values, colorspace):
        rgb = self.sp.to_rgb(values, wavelengths, colorspace=colorspace, mode="emission",
                             **self.to_rgb_options)
        return self.np.asarray(rgb, dtype=self.np.float64)

    def emitted_xyz(self, xyz, basis):
        """The XYZ of the spectrum the white-balanced XYZ `xyz` becomes with `basis`."""
        return self.measured(*self.spectrum(xyz, XYZ_ROLE, basis), XYZ_ROLE)

    def xyz(self, rgb):
        return self.measured(*self.spectrum(rgb, self.space, "flat"), XYZ_ROLE) * self.balance

    def rgb(self, xyz):
        return self.measured(*self.spectrum(xyz / self.balance, XYZ_ROLE, "flat"), self.space)


def _colour_temperature_spectrum(r, kelvin, options):
    """UsdLux's colour temperature: a Planckian radiator at `kelvin` (Planck's law), luminance
    normalised (Y = 1 at intensity 1, exposure 0), whose RGB in the rendering frame the light's
    color multiplies; the spectrum reproduces that product exactly and is the radiator itself
    for a white color."""
    planck = "%.17gK" % kelvin
    frame = _Frame(r["colorspace"], r["basis"], options)
    t_xyz = frame.emitted_xyz(D65_WHITE, planck)  # the radiator, Y = 1
    target = frame.xyz(frame.np.asarray(r["color"]) * frame.rgb(t_xyz) * r["scale"])
    # The spectrum with the radiator as its basis: its white balance takes D65 to t_xyz.
    return frame.spectrum(target * frame.np.asarray(D65_WHITE) / t_xyz, XYZ_ROLE, planck)


def _rendering_space(stage):
    """The stage's rendering colour space, as Hydra finds it: the renderingColorSpace of the
    RenderSettings prim its renderSettingsPrimPath metadata names (else of its only
    RenderSettings prim), and why; (None, why not) where several are there and none is named,
    (None, None) where none declares one. Cost: O(prims)."""
    from pxr import UsdRender
    settings = UsdRender.Settings.GetStageRenderSettings(stage)
    how = "the stage's renderSettingsPrimPath"
    if not settings:
        found = [p for p in stage.Traverse() if p.IsA(UsdRender.Settings)]
        if len(found) > 1:
            return None, "%d RenderSettings prims and no renderSettingsPrimPath names one" % (
                len(found))
        if not found:
            return None, None
        settings, how = UsdRender.Settings(found[0]), "the stage's only RenderSettings"
    attr = settings.GetRenderingColorSpaceAttr()
    if not attr or not attr.HasAuthoredValue():
        return None, None
    name = str(attr.Get())
    return name, "renderingColorSpace '%s' of <%s> (%s)" % (name, settings.GetPath(), how)


def _light_times(light):
    """The times at which any input lights() reads is sampled, sorted; [] for a light whose
    inputs have only defaults."""
    attrs = (light.GetColorAttr(), light.GetIntensityAttr(), light.GetExposureAttr(),
             light.GetEnableColorTemperatureAttr(), light.GetColorTemperatureAttr())
    return sorted({t for a in attrs if a for t in a.GetTimeSamples()})


def _light_sample(light, r, time, options):
    """The light's spectrum at `time` (a Usd.TimeCode), in the space and basis of the record
    `r`: a dict of "color", "scale", "basis", "basis_reason" (and "color_temperature",
    "rendering_basis" for a colour temperature), "wavelengths", "values"; or of "failure"."""
    import numpy as np
    import spectralize

    s = {}
    colour = light.GetColorAttr().Get(time)
    s["color"] = [float(c) for c in (colour if colour is not None else (1.0, 1.0, 1.0))]
    intensity = light.GetIntensityAttr().Get(time)
    exposure = light.GetExposureAttr().Get(time)
    s["scale"] = float(1.0 if intensity is None else intensity) * 2.0 ** float(
        0.0 if exposure is None else exposure)
    kelvin = None
    if light.GetEnableColorTemperatureAttr().Get(time):
        authored = light.GetColorTemperatureAttr().Get(time)
        kelvin = float(6500.0 if authored is None else authored)
        s["color_temperature"] = kelvin
    low, high = COLOR_TEMPERATURE_RANGE
    if kelvin is not None and not low <= kelvin <= high:
        return {"failure": "inputs:colorTemperature %g K is outside UsdLux's valid range, "
                           "%g..%g K" % (kelvin, low, high)}
    if min(s["color"]) < 0 or s["scale"] < 0:
        return {"failure": "a negative colour or intensity: no light has it"}
    s["basis"], s["basis_reason"] = r["basis"], r["basis_reason"]
    rgb = np.asarray(s["color"], dtype=np.float64) * s["scale"]
    try:
        if r.get("textured"):
            # The texture's spectral file holds its emission (the rendering illuminant and
            # all); the light's colour, intensity and exposure multiply it: a tint, flat for
            # white, the colour exact under the equal-energy white (basis "flat").
            if kelvin is not None:
                frame = _Frame(r["colorspace"], r["basis"], options)
                rgb = rgb * frame.rgb(frame.emitted_xyz(D65_WHITE, "%.17gK" % kelvin))
            s["wavelengths"], s["values"] = _tint_spectrum(rgb, r["colorspace"], options)
            s["rendering_basis"], s["basis"] = r["basis"], "flat"
            s["basis_reason"] = (
                "a light with a texture: a tint its texture's emission is multiplied by (flat "
                "for white)%s" % (", the colour times the RGB of a Planckian radiator at %g K"
                                  % kelvin if kelvin is not None else ""))
        elif kelvin is None:
            s["wavelengths"], s["values"] = spectralize.spectra(
                rgb, colorspace=r["colorspace"], mode="emission", emission_basis=r["basis"],
                **options)
        else:
            s["wavelengths"], s["values"] = _colour_temperature_spectrum(
                dict(r, **s), kelvin, options)
            s["rendering_basis"] = r["basis"]
            s["basis"] = "%.17gK" % kelvin
            s["basis_reason"] = (
                "inputs:colorTemperature: a Planckian radiator at %g K, luminance "
                "normalised; inputs:color multiplies its RGB in the rendering space "
                "(white-balanced to %s)" % (kelvin, r["basis"]))
    except ValueError as e:  # a space the config lacks: this light's failure
        return {"failure": str(e).split(". Valid names")[0]}
    return s


def _d_series_at_white(space, config):
    """The CIE D-series illuminant at the white of `space` (a config's name, alias or interop
    ID; the primaries part of its interop ID names the white): "D65", "D60", or None where no
    D-series illuminant is known there. ValueError for a space the config lacks."""
    import spectralize
    parts = (spectralize.colour_space(space, **config)["interop_id"] or "").split("_")
    return D_SERIES_WHITE.get(parts[1]) if len(parts) == 3 else None


def _unknown_space_said(error):
    """A ValueError of colour_space() as a light's failure says it (without the list of names)."""
    return str(error).split(". Valid names")[0].split("colorspace: ", 1)[-1]


def _tint_spectrum(rgb, colorspace, options):
    """A multiplier spectrum for the RGB `rgb` of `colorspace`: its colour white-balanced from
    the space's white to the equal-energy white (XYZ scaling, docs/DESIGN.md §3), so white
    (1, 1, 1) is flat 1 and every colour is exact under the equal-energy white."""
    frame = _Frame(colorspace, "flat", options)
    np = frame.np
    xyz = frame.measured(*frame.spectrum(rgb, colorspace, "flat"), XYZ_ROLE)  # D65-referred
    grid, _ = frame.spectrum(np.asarray(D65_WHITE), XYZ_ROLE, "flat")
    equal_energy = frame.measured(grid, np.ones_like(grid), XYZ_ROLE)
    return frame.spectrum(xyz * equal_energy / np.asarray(D65_WHITE), XYZ_ROLE, "flat")


def lights(stage, **options):
    """The emission spectrum of every UsdLux light of `stage` (a path or a Usd.Stage), as UsdLux
    asks: inputs:color (in its own colorSpace metadata, else the UsdColorSpaceAPI space in
    force at the light, else lin_rec709_scene) times inputs:intensity times
    2^inputs:exposure, with the CIE D-series illuminant at the rendering space's white as the
    emission basis (spectralize.spectra(), mode emission): white (1, 1, 1) is that illuminant
    itself and every colour is reproduced exactly, white-balanced to it (D65 for the D65
    spaces; D60 for ACES, whose white is no D-series white: the record says so). The rendering
    space is the renderingColorSpace of the stage's RenderSettings (the one its
    renderSettingsPrimPath names, else its only one; record "rendering_colorspace"), else the
    light's own. A light with inputs:enableColorTemperature is a
    Planckian radiator at inputs:colorTemperature (Planck's law, luminance normalised: Y = 1 at
    intensity 1 and exposure 0), its RGB in the rendering space multiplied by inputs:color
    (UsdLux: "the computed result multiplies against the color attribute"): a white color
    gives the radiator itself; record "color_temperature", "basis" "<T>K". options:
    spectra()'s (wavelengths, model, config, ...). Each record: "prim", "type", "colorspace",
    "colorspace_reason", "color", "scale", "basis", "basis_reason", "wavelengths", "values"
    (NumPy arrays); a light that cannot be made has "failure" instead (a negative colour, a
    colour temperature outside UsdLux's 1000..10000 K, a space whose white no D-series
    illuminant is, a space the config has no space for). A light whose inputs are animated
    (time samples) has one spectrum per time at which any of them is sampled: "times", and
    "samples" (per time: "time", "color", "scale", "basis", ...) instead of the per-light
    keys, "values" one row per time; it fails if any time fails, naming the time. An option
    spectra() refuses raises for the first light. Cost: composing the stage, one spectrum per
    light and time sample. A light with a texture (inputs:texture:file: a DomeLight's sky, a
    RectLight's picture, whose emission textures() gives) has "textured" and, as UsdLux
    multiplies the texture by the light's colour, a tint: basis "flat", flat for white (the
    colour times intensity times 2^exposure, exact under the equal-energy white). A
    PortalLight, which emits nothing of its own, has "not_made" (why) and no spectrum."""
    import numpy as np

    _, Usd, UsdLux, _ = _pxr()
    stage = _open(stage)
    config = {k: v for k, v in options.items() if k == "config"}
    # The rendering space, once for all lights: its white names the D-series illuminant that
    # white light is (else each light's own space's does).
    rendering, rendering_why = _rendering_space(stage)
    rendering_basis, rendering_failure = None, None
    if rendering:
        try:
            rendering_basis = _d_series_at_white(rendering, config)
        except ValueError as e:
            rendering_failure = "%s (%s)" % (_unknown_space_said(e), rendering_why)
    out = []
    for prim in stage.Traverse(Usd.TraverseInstanceProxies()):
        if not prim.HasAPI(UsdLux.LightAPI):
            continue
        light = UsdLux.LightAPI(prim)
        r = {"prim": str(prim.GetPath()), "type": str(prim.GetTypeName())}
        if prim.IsA(UsdLux.PortalLight):  # it guides a dome light's emission, emits none
            r["not_made"] = ("a PortalLight emits nothing of its own: it guides the DomeLight's "
                             "light, which its color and intensity tint")
            out.append(r)
            continue
        r["colorspace"], r["colorspace_reason"] = _space_in_force(
            prim, "lin_rec709_scene",
            "the stage declares none: OpenUSD's default, lin_rec709_scene", light.GetColorAttr())
        if rendering:
            r["rendering_colorspace"], r["rendering_colorspace_reason"] = rendering, rendering_why
        failure, r["basis"] = None, None
        try:  # the light's own space, as the config has it (by name, alias or interop ID)
            r["basis"] = _d_series_at_white(r["colorspace"], config)
        except ValueError as e:
            failure = "%s (%s)" % (_unknown_space_said(e), r["colorspace_reason"])
        if rendering and not failure:
            failure, r["basis"] = rendering_failure, rendering_basis
        if not failure and r["basis"] is None:
            failure = "colour space '%s': no CIE D-series illuminant is known at its white" % (
                rendering or r["colorspace"])
        r["basis_reason"] = "the D-series illuminant at the white of %s" % (
            "the rendering space, %s" % rendering_why if rendering else
            "the light's space (the stage declares no renderingColorSpace%s)" % (
                ": " + rendering_why if rendering_why else ""))
        if r["basis"] == "D60":
            r["basis_reason"] += ("; the ACES white is no D-series white: D60, the nearest "
                                  "(colours are white-balanced to it: white light is D60)")
        texture = prim.GetAttribute("inputs:texture:file")
        if texture and (texture.HasAuthoredValue() or texture.GetNumTimeSamples()):
            r["textured"] = True  # its spectrum tints its texture's (textures())
        times = _light_times(light)
        samples = []
        for t in (times or [None]):
            if failure:
                break
            s = _light_sample(light, r, Usd.TimeCode.Default() if t is None else Usd.TimeCode(t),
                              options)
            if "failure" in s:
                failure = s["failure"] if t is None else "at time %g: %s" % (t, s["failure"])
            else:
                s["time"] = t
                samples.append(s)
        if failure:
            r["failure"] = "<%s>: %s" % (r["prim"], failure)
            out.append(r)
            continue
        if not times:
            r.update({k: v for k, v in samples[0].items() if k != "time"})
        else:  # animated: a spectrum per time
            r.pop("basis")
            r["times"] = times
            r["wavelengths"] = samples[0]["wavelengths"]
            r["values"] = np.stack([s.pop("values") for s in samples])
            for s in samples:
                s.pop("wavelengths")
            r["samples"] = samples
        out.append(r)
    return out
