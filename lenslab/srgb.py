"""The sRGB transfer function, in one place for the whole of lenslab.

IEC 61966-2-1:1999 (the sRGB standard), as colour-science defines it (``colour.models.eotf_sRGB``
and ``eotf_inverse_sRGB``); the tests hold these to colour-science's answers at float64 precision.

- decoding, code value ``v`` in [0, 1] -> linear light: ``v / 12.92`` up to ``v = 0.04045``, else
  ``((v + 0.055) / 1.055) ** 2.4``;
- encoding, linear ``x`` -> code value: ``12.92 x`` up to ``x = 0.0031308``, else
  ``1.055 x ** (1 / 2.4) - 0.055``.

Written here with NumPy alone so that reading or writing an 8-bit file needs no colour-science import
(which takes about a second). The file formats build their lookup tables from these
(:mod:`lenslab.io.encode`), the tone curves take the constants (``gamma``), the fits compare
encoded values.

>>> float(eotf(0.5))
0.21404114048223255
>>> float(eotf_inverse(0.18))
0.46135612950044164
"""

from __future__ import annotations

import numpy as np

#: linear value where the two segments of the encoding meet
KNEE_LINEAR = 0.0031308
SLOPE = 12.92
#: code value where the decoding changes segment: the encoding of KNEE_LINEAR, 0.040449936 (the
#: standard rounds it to 0.04045; colour-science switches here, where the segments agree to 2e-9)
KNEE = KNEE_LINEAR * SLOPE
OFFSET = 0.055
POWER = 2.4


def eotf(code) -> np.ndarray:
    """sRGB code values (any float array) -> linear light, float64; values outside [0, 1] follow the
    same two segments (the power one mirrored below 0, as colour-science does not: it is not used there)."""
    v = np.asarray(code, dtype=np.float64)
    return np.where(v <= KNEE, v / SLOPE, ((np.maximum(v, KNEE) + OFFSET) / (1.0 + OFFSET)) ** POWER)


def eotf_inverse(linear) -> np.ndarray:
    """Linear light -> sRGB code values, float64 (inputs below 0 stay on the linear segment)."""
    x = np.asarray(linear, dtype=np.float64)
    return np.where(x <= KNEE_LINEAR, x * SLOPE,
                    (1.0 + OFFSET) * np.maximum(x, KNEE_LINEAR) ** (1.0 / POWER) - OFFSET)


def encode(linear) -> np.ndarray:
    """Linear light -> sRGB code values in [0, 1], float32 of the same shape: NaN and values below 0
    become 0, values above 1 (and +inf) become 1, then :func:`eotf_inverse`."""
    x = np.nan_to_num(np.asarray(linear, dtype=np.float64), nan=0.0, posinf=1.0, neginf=0.0)
    return eotf_inverse(np.clip(x, 0.0, 1.0)).astype(np.float32)
