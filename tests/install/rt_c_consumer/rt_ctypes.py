"""Loads the installed libspectralize_rt with Python's ctypes (no compiler, no spectralize
module) and fetches a colour: what a Blender add-on or a notebook does.
Usage: python3 rt_ctypes.py LIBRARY TABLE.spztab"""
import ctypes
import math
import sys


class Spectrum(ctypes.Structure):
    """spz_spectrum of <spectralize/rt.h>: 48 bytes."""
    _fields_ = [("table", ctypes.c_void_p), ("vertex", ctypes.c_uint32 * 4),
                ("weight", ctypes.c_float * 4), ("scale", ctypes.c_float),
                ("flags", ctypes.c_uint32)]


lib = ctypes.CDLL(sys.argv[1])
lib.spz_table_load.restype = ctypes.c_void_p
lib.spz_table_load.argtypes = [ctypes.c_char_p, ctypes.c_char_p, ctypes.c_size_t]
lib.spz_fetch.argtypes = [ctypes.c_void_p, ctypes.POINTER(ctypes.c_float),
                          ctypes.POINTER(Spectrum)]
lib.spz_eval.restype = ctypes.c_float
lib.spz_eval.argtypes = [ctypes.POINTER(Spectrum), ctypes.c_float]
lib.spz_table_free.argtypes = [ctypes.c_void_p]
assert ctypes.sizeof(Spectrum) == 48
error = ctypes.create_string_buffer(512)
table = lib.spz_table_load(sys.argv[2].encode(), error, 512)
assert table, error.value
rgb = (ctypes.c_float * 3)(0.2, 0.5, 0.1)
s = Spectrum()
status = lib.spz_fetch(table, rgb, ctypes.byref(s))
values = [lib.spz_eval(ctypes.byref(s), float(nm)) for nm in range(380, 781, 5)]
assert status == 0 and all(0 <= v <= 1 and math.isfinite(v) for v in values), (status, values)
assert not lib.spz_table_load(b"/nonexistent.spztab", error, 512)
assert b"/nonexistent.spztab" in error.value, error.value
lib.spz_table_free(table)
print("ctypes ok", status, round(values[34], 4))
