"""The guide's Mitsuba 3 example (docs/guide/mitsuba.md): an albedo texture uplifted at render
time (spectralize_rgb), the same texture's spectral OpenEXR (spectral_bitmap) and a spectralized
HDRI (spectral_envmap), in llvm_ad_spectral.
Usage: python mitsuba_scene.py OUTPUT.png [spp]   (spectralize on PATH or $SPECTRALIZE_EXE)"""
import os
import pathlib
import subprocess
import sys

import mitsuba as mi

mi.set_variant("llvm_ad_spectral")
import spectralize.mitsuba  # noqa: E402  (after the variant: the plugins are made for it)

spectralize.mitsuba.register()

here = pathlib.Path(__file__).resolve().parent
images = here.parent.parent / "testimages"
out = pathlib.Path(sys.argv[1])
spp = int(sys.argv[2]) if len(sys.argv) > 2 else 64
exe = os.environ.get("SPECTRALIZE_EXE", "spectralize")

# The spectral files, as Mitsuba integrates: 360-830 nm and its colour matching functions.
as_mitsuba = ["--wavelengths", "360:830:5", "--observer", "cie1931_mitsuba", "-q"]
albedo = images / "colorchecker_srgb8.png"
albedo_exr = out.with_name("colorchecker_spectral.exr")
sky_exr = out.with_name("sunset_spectral.exr")
subprocess.run([exe, str(albedo), "-o", str(albedo_exr), *as_mitsuba], check=True)
subprocess.run([exe, str(images / "hdri_sunset_256x128.exr"), "-o", str(sky_exr), "--format",
                "float", *as_mitsuba], check=True)

T = mi.ScalarTransform4f
scene = mi.load_dict({
    "type": "scene",
    "integrator": {"type": "path", "max_depth": 6},
    "sensor": {"type": "perspective", "fov": 38,
               "to_world": T().look_at(origin=[0, 1.2, 4.2], target=[0, 0.1, 0], up=[0, 1, 0]),
               "film": {"type": "hdrfilm", "width": 480, "height": 320},
               "sampler": {"type": "independent", "sample_count": spp}},
    # The albedo texture, uplifted through a spectralize table made on first use.
    "sphere": {"type": "sphere", "to_world": T().translate([-0.6, 0.0, 0]) @ T().scale(0.7),
               "bsdf": {"type": "diffuse",
                        "reflectance": {"type": "spectralize_rgb", "filename": str(albedo)}}},
    # The same texture, from its spectral OpenEXR (spectralize's output).
    "box": {"type": "cube", "to_world": T().translate([0.9, -0.25, 0.2]) @ T().rotate([0, 1, 0], 30)
            @ T().scale(0.45),
            "bsdf": {"type": "diffuse",
                     "reflectance": {"type": "spectral_bitmap", "filename": str(albedo_exr)}}},
    "floor": {"type": "rectangle",
              "to_world": T().translate([0, -0.7, 0]) @ T().rotate([1, 0, 0], -90) @ T().scale(4),
              "bsdf": {"type": "diffuse", "reflectance": {"type": "uniform", "value": 0.5}}},
    # The HDRI, spectralized: importance-sampled by luminance like Mitsuba's envmap.
    "sky": {"type": "spectral_envmap", "filename": str(sky_exr), "scale": 1.0},
})
image = mi.render(scene)
mi.Bitmap(image).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.UInt8, True).write(str(out))
print("rendered %s: %dx%d, %d spp, llvm_ad_spectral" % (out.name, 480, 320, spp))
