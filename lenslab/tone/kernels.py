"""What every curve's kernel is made of: float32 constants, the clip ufunc and the rational form.

A kernel is ``k(src, dst, scratch)`` on float32 blocks: 1-D for values, planar ``(3, n)`` for the RGB
kernels of ``"rgb"`` curves. ``src`` holds repaired values (finite, >= 0; it may be ``dst``), ``scratch``
is a list of two float32 buffers of the block's shape. Exposure is folded in: each builder gets
``scale = 2**EV`` and bakes it into its constants, so one sweep through memory does the exposure and
the curve.

Order: every kernel is monotone in float32 itself, not only on paper. The rational curves are
evaluated in a form whose every step is a rounded monotone operation (the plain ratio of two
increasing polynomials can step back by an ulp between neighbouring inputs). Powers are float32
log2/exp2 pairs whose arguments are kept away from log2(0) and from denormal results of exp2 (NumPy's
SIMD loops leave their fast path there and run 10 to 100 times slower: a black border would otherwise
cost more than the rest of the image); the offset this floor leaves is subtracted, so 0 still maps to
exactly 0.

Pixel kernels: where NumPy's passes cannot reach the speed a curve needs, its per-channel kernel is
compiled (``lenslab.cxx_kernels``, :func:`native`): ``k(src, dst) -> int`` on contiguous ``(m, 3)``
float32 blocks of interleaved pixels in one pass, returning the largest bit pattern it read (at or above
+inf's, the block held bad values and :mod:`lenslab.tone.sweep` runs it again on a repaired copy). The
NumPy kernel stays as the reference the tests hold it to, and runs where the extension is not built.
"""

from __future__ import annotations

import numpy as np

from lenslab.errors import ToneError

F32 = np.float32
TINY = F32(1e-37)  # smallest luminance divided by (below it a pixel is black to float32)
BIG = F32(1e15)  # inputs are capped here where a curve squares them (1e30 still fits in float32)
FMAX = F32(np.finfo(np.float32).max)
# the clip ufunc itself: np.clip's argument handling costs ~3 us a call, more than clipping a block
# in cache; where numpy does not expose it, np.clip does the same
clip = getattr(getattr(getattr(np, "_core", None), "umath", None), "clip", None) or np.clip


NATIVE: bool | None = None  # None: the compiled pixel kernels where built; False forces NumPy's (tests)


def native():
    """The compiled kernels (``lenslab.cxx_kernels``), or None where this copy of lenslab was installed
    without them or :data:`NATIVE` is False."""
    if NATIVE is False:
        return None
    try:
        from lenslab import cxx_kernels
    except ImportError:  # a source tree used without `pip install -e .`
        return None
    return cxx_kernels


def pixel_kernel(fn):
    """Mark ``fn(src, dst) -> int`` as a kernel on interleaved ``(m, 3)`` pixels (see above)."""
    fn.pixels = True
    return fn


def rational_kernel(a1, a0, b1, b0, cap):
    """y = x (a1 x + a0) / (x (b1 x + b0) + 1) on min(x, cap), clipped to [0, 1].

    Evaluated as 1 / y = b1/a1 + m / (a1 x + a0) + 1 / (x (a1 x + a0)), m = b0 - b1 a0 / a1 >= 0:
    every step is a rounded monotone operation, so the float32 result never steps back (the plain
    ratio of two increasing polynomials wobbles by an ulp), and x = 0 gives 1/inf = exactly 0.
    """
    m = b0 - b1 * a0 / a1
    if a1 <= 0 or a0 < 0 or b1 < 0 or m < 0:  # pragma: no cover - the curves' parameters rule this out
        raise ToneError("internal: rational curve coefficients are not of the monotone form")
    a1, a0, k, m, cap = F32(a1), F32(a0), F32(b1 / a1), F32(m), F32(cap)

    def k_(src, dst, scratch):
        t, u = scratch
        clip(src, F32(0), cap, out=dst)
        np.multiply(dst, a1, out=t)
        t += a0
        np.multiply(dst, t, out=u)
        np.divide(F32(1), u, out=u)
        np.divide(m, t, out=t)
        t += u
        t += k
        np.divide(F32(1), t, out=dst)
        clip(dst, F32(0), F32(1), out=dst)
    return k_


def power_offset(floor: float, power: float, dtype=np.float32):
    """``floor ** power`` computed with the same log2/exp2 steps as the kernels (the value a kernel
    subtracts so that its floor maps to exactly 0)."""
    f = np.full(16, floor, dtype)
    np.log2(f, out=f)
    f *= dtype(power)
    np.exp2(f, out=f)
    return dtype(f[0])
