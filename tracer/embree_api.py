"""Embree's C API, for the compiled passes: the library that embreex ships, called per ray from C++.

The compiled bounce loop (:mod:`tracer.wavefront`) casts its rays itself, one ``rtcIntersect1`` or
``rtcOccluded1`` per ray inside the pass (``src/native/tracer_paths.cpp``, which takes the entry points'
addresses from here), instead of a round trip through embreex's arrays per bounce.
It does so on a scene of its own, built here through the same library with the same settings as
embreex's (``RTC_SCENE_FLAG_ROBUST``), so that every hit, primitive and distance is the same bit for bit
as :meth:`tracer.accel.Accelerator.intersect` gives (a test checks it on random rays).

``RTCRayHit`` (embree 4, one instance level) as 32-bit words: ``org`` 0-2, ``tnear`` 3, ``dir`` 4-6,
``time`` 7, ``tfar`` 8, ``mask`` 9, ``id`` 10, ``flags`` 11, then the hit: ``Ng`` 12-14, ``u`` 15, ``v`` 16,
``primID`` 17, ``geomID`` 18, ``instID`` 19 (and ``instPrimID`` 20 where built in); 16-byte aligned.
"""

from __future__ import annotations

import ctypes
import glob
import os
import weakref

import numpy as np

RTC_SCENE_FLAG_ROBUST = 1 << 2
RTC_GEOMETRY_TYPE_TRIANGLE = 0
RTC_BUFFER_TYPE_INDEX, RTC_BUFFER_TYPE_VERTEX = 0, 1
RTC_FORMAT_UINT3, RTC_FORMAT_FLOAT3 = 0x5003, 0x9003
INVALID = 0xFFFFFFFF
RAYHIT_WORDS = 24  # 96 bytes: RTCRay (48) and RTCHit (48 with its padding)

_LIB = None


def library() -> ctypes.CDLL:
    """embree 4 as embreex ships it, loaded once."""
    global _LIB
    if _LIB is None:
        import embreex

        here = os.path.dirname(embreex.__file__)
        found = sorted(glob.glob(os.path.join(here, "..", "embreex.libs", "libembree4*.so*"))
                       + glob.glob(os.path.join(here, ".dylibs", "libembree4*")) + glob.glob(os.path.join(here, "embree4*.dll")))
        if not found:
            raise ImportError("embree 4's library was not found beside embreex")
        lib = ctypes.CDLL(found[0])
        vp = ctypes.c_void_p
        for name, res, args in (("rtcNewDevice", vp, [ctypes.c_char_p]), ("rtcNewScene", vp, [vp]),
                                ("rtcSetSceneFlags", None, [vp, ctypes.c_int]),
                                ("rtcNewGeometry", vp, [vp, ctypes.c_int]),
                                ("rtcSetNewGeometryBuffer", vp, [vp, ctypes.c_int, ctypes.c_uint, ctypes.c_int,
                                                                 ctypes.c_size_t, ctypes.c_size_t]),
                                ("rtcCommitGeometry", None, [vp]), ("rtcAttachGeometry", ctypes.c_uint, [vp, vp]),
                                ("rtcReleaseGeometry", None, [vp]), ("rtcCommitScene", None, [vp]),
                                ("rtcReleaseScene", None, [vp]), ("rtcReleaseDevice", None, [vp])):
            fn = getattr(lib, name)
            fn.restype, fn.argtypes = res, args
        _LIB = lib
    return _LIB


def available() -> bool:
    """Whether embree's library could be found and loaded (else the NumPy steps and embreex do the work)."""
    try:
        library()
    except (ImportError, OSError):
        return False
    return True


class RtcScene:
    """One triangle mesh as an embree scene; ``handle`` is its ``RTCScene`` pointer for the kernels."""

    def __init__(self, vertices: np.ndarray, triangles: np.ndarray):
        lib = library()
        v = np.ascontiguousarray(vertices, dtype=np.float32)
        t = np.ascontiguousarray(triangles, dtype=np.uint32)
        device = lib.rtcNewDevice(None)
        scene = lib.rtcNewScene(device)
        lib.rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST)
        if len(t):
            geom = lib.rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE)
            for kind, fmt, arr in ((RTC_BUFFER_TYPE_VERTEX, RTC_FORMAT_FLOAT3, v), (RTC_BUFFER_TYPE_INDEX, RTC_FORMAT_UINT3, t)):
                dst = lib.rtcSetNewGeometryBuffer(geom, kind, 0, fmt, 12, len(arr))
                if not dst:
                    raise MemoryError("embree could not allocate the mesh's buffers")
                ctypes.memmove(dst, arr.ctypes.data, arr.nbytes)
            lib.rtcCommitGeometry(geom)
            lib.rtcAttachGeometry(scene, geom)
            lib.rtcReleaseGeometry(geom)
        lib.rtcCommitScene(scene)
        self.handle = int(scene)
        self._release = weakref.finalize(self, _release, lib, scene, device)


def _release(lib, scene, device) -> None:
    lib.rtcReleaseScene(scene)
    lib.rtcReleaseDevice(device)


def entry_points(packet: int = 1) -> tuple[int, int]:
    """The addresses of ``rtcIntersect<packet>`` (1, 4, 8 or 16) and ``rtcOccluded1`` in that library."""
    lib = library()
    return tuple(ctypes.cast(getattr(lib, name), ctypes.c_void_p).value
                 for name in (f"rtcIntersect{packet}", "rtcOccluded1"))
