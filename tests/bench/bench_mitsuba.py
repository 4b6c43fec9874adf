"""Render time in Mitsuba 3 (llvm_ad_spectral): one scene (a textured sphere on a textured floor,
lit by Mitsuba's d65 sky, path tracer to depth 4) with Mitsuba's bitmap and with
spectralize_rgb on the same texture, same spp, alternating, after a warm-up render each (the
JIT's compilation is not timed); prints the medians and their ratio. Run by make bench through
the project's virtual environment.
Usage: python bench_mitsuba.py [runs] [texture]"""
import statistics
import sys
import time

import drjit as dr
import mitsuba as mi

mi.set_variant("llvm_ad_spectral")
import spectralize.mitsuba  # noqa: E402

spectralize.mitsuba.register()

runs = int(sys.argv[1]) if len(sys.argv) > 1 else 5
texture = sys.argv[2] if len(sys.argv) > 2 else None


def scene(tex, res=384, spp=64):
    return mi.load_dict({
        "type": "scene", "integrator": {"type": "path", "max_depth": 4},
        "sensor": {"type": "perspective", "fov": 40,
                   "to_world": mi.ScalarTransform4f().look_at(origin=[0, 1, 4], target=[0, 0, 0],
                                                              up=[0, 1, 0]),
                   "film": {"type": "hdrfilm", "width": res, "height": res},
                   "sampler": {"type": "independent", "sample_count": spp}},
        "sphere": {"type": "sphere", "bsdf": {"type": "diffuse", "reflectance": tex}},
        "floor": {"type": "rectangle",
                  "to_world": mi.ScalarTransform4f().translate([0, -1, 0])
                  @ mi.ScalarTransform4f().rotate([1, 0, 0], -90) @ mi.ScalarTransform4f().scale(6),
                  "bsdf": {"type": "diffuse", "reflectance": tex}},
        "light": {"type": "constant", "radiance": {"type": "d65"}}})


def timed(s):
    t0 = time.perf_counter()
    dr.eval(mi.render(s, seed=int(t0 * 1000) % 1000))
    dr.sync_thread()
    return time.perf_counter() - t0


cases = {"bitmap": {"type": "bitmap", "filename": texture},
         "spectralize_rgb": {"type": "spectralize_rgb", "filename": texture},
         "spectralize_rgb (blends: textures beyond memory=)":
             {"type": "spectralize_rgb", "filename": texture, "memory": 0}}
scenes = {name: scene(tex) for name, tex in cases.items()}
for s in scenes.values():
    timed(s)  # compile
times = {name: [] for name in cases}
for _ in range(runs):
    for name, s in scenes.items():
        times[name].append(timed(s))
base = statistics.median(times["bitmap"])
print("Mitsuba %s, llvm_ad_spectral, %s, 384x384 at 64 spp, path depth 4, median of %d:"
      % (mi.__version__, texture, runs))
for name, t in times.items():
    m = statistics.median(t)
    print("  %-52s %.3f s  %.2fx" % (name, m, m / base))
