"""The sRGB transfer function, in one place for the whole of lenslab: colour-science's, and tables of it.

IEC 61966-2-1:1999 as colour-science implements it (``colour.models.eotf_sRGB`` and
``eotf_inverse_sRGB``): decoding takes a code value ``v`` in [0, 1] to linear light, ``v / 12.92`` up
to 0.04045, ``((v + 0.055) / 1.055) ** 2.4`` above; encoding is its inverse. :func:`eotf` and
:func:`eotf_inverse` are colour-science's functions themselves.

Importing colour-science takes about a second, too long for a command that reads or writes one small
file. So the formats and the tone curves use tables of those functions, built with colour-science the
first time they are needed and kept as ``.npy`` files in the user's cache directory
(``$LENSLAB_CACHE_DIR``, else ``$XDG_CACHE_HOME/lenslab``, else ``~/.cache/lenslab``; where nothing
can be written the tables are built in memory each time):

- :func:`decode_table` (maxval 255, 1023, 4095 or 65535 cached): every code value's linear light, as float32;
- :func:`thresholds`: the linear values where the rounded 8- or 16-bit code steps up (exact table
  encoding, :mod:`lenslab.io.encode`);
- :func:`encode`: linear light to code values in float32 by linear interpolation in a table of 65537
  points over the curved segment, within 1e-7 of colour-science (the tests hold it there).

The standard's constants (:data:`KNEE` ...) are here too, for the ``gamma`` tone curve's closed form.

>>> round(float(encode([0.18])[0]), 6), round(float(decode_table(255)[118]), 6)   # middle grey
(0.461356, 0.181164)
"""

from __future__ import annotations

import contextlib
import functools
import os
import sys
from pathlib import Path

import numpy as np

#: linear value where the encoding changes segment
KNEE_LINEAR = 0.0031308
SLOPE = 12.92
#: code value where the decoding changes segment: the encoding of KNEE_LINEAR, 0.040449936 (the
#: standard rounds it to 0.04045; colour-science switches here, where the segments agree to 2e-9)
KNEE = KNEE_LINEAR * SLOPE
OFFSET = 0.055
POWER = 2.4

ENCODE_POINTS = 1 << 16  # intervals of the encoding table over [0, 1]
_CACHE_VERSION = 2


def eotf(code) -> np.ndarray:
    """sRGB code values -> linear light, float64 (colour-science's ``eotf_sRGB``)."""
    colour = colour_science()
    return np.asarray(colour.models.eotf_sRGB(np.asarray(code, dtype=np.float64)), dtype=np.float64)


def eotf_inverse(linear) -> np.ndarray:
    """Linear light -> sRGB code values, float64 (colour-science's ``eotf_inverse_sRGB``)."""
    colour = colour_science()
    return np.asarray(colour.models.eotf_inverse_sRGB(np.asarray(linear, dtype=np.float64)), dtype=np.float64)


def cache_dir() -> Path:
    """Where the tables are kept (see the module's description)."""
    env = os.environ.get("LENSLAB_CACHE_DIR")
    if env:
        return Path(env)
    xdg = os.environ.get("XDG_CACHE_HOME")
    return (Path(xdg) if xdg else Path.home() / ".cache") / "lenslab"


def cached_table(name: str, length: int, dtype, build, prefix: str = f"srgb-v{_CACHE_VERSION}") -> np.ndarray:
    """The table ``name`` from the cache (checked for its length and type), else ``build()`` and keep it."""
    path = cache_dir() / f"{prefix}-{name}.npy"
    try:
        table = np.load(path, allow_pickle=False)
        if table.shape == (length,) and table.dtype == dtype:
            return table
    except (OSError, ValueError, EOFError):  # missing, damaged or cut short: build it again
        pass
    table = np.ascontiguousarray(build(), dtype=dtype)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
        with open(tmp, "wb") as f:
            np.save(f, table, allow_pickle=False)
        os.replace(tmp, path)  # whole or not at all: another process may be reading it
    except OSError:
        pass  # a read-only home: the table is rebuilt next time
    return table


@contextlib.contextmanager
def matplotlib_quiet():
    """Within the block, matplotlib's warnings are not printed (only its errors): where the cache folder cannot be
    made, colour-science's import of matplotlib would print two lines of its own on each command (a folder it could
    not make, and the temporary one it used instead). The logger's level is put back after the block."""
    if "matplotlib" in sys.modules:  # (imported already: nothing more it says on import)
        yield
        return
    import logging

    log = logging.getLogger("matplotlib")
    level = log.level
    log.setLevel(logging.ERROR)
    try:
        yield
    finally:
        log.setLevel(level)


def colour_science():
    """The ``colour`` module (colour-science), imported inside :func:`matplotlib_quiet`: every lenslab module that
    needs it calls this rather than importing it."""
    with matplotlib_quiet():  # (colour-science imports matplotlib)
        import colour
    return colour


@functools.lru_cache(maxsize=8)
def decode_table(maxval: int) -> np.ndarray:
    """float32 table: code value 0..maxval -> linear light (the EOTF of code / maxval)."""
    maxval = int(maxval)

    def build():
        return eotf(np.arange(maxval + 1, dtype=np.float64) / maxval)
    if maxval not in (255, 1023, 4095, 65535):  # 8 and 16 bits, and the 10 and 12 bits of HEIF photos
        return build().astype(np.float32)
    return cached_table(f"decode-{maxval}", maxval + 1, np.float32, build)


@functools.lru_cache(maxsize=2)
def thresholds(bits: int) -> np.ndarray:
    """float64: the linear value at which the rounded ``bits``-bit code reaches k, for k = 1..2^bits - 1
    (the EOTF of (k - 0.5) / maxval)."""
    maxval = (1 << int(bits)) - 1
    return cached_table(f"thresholds-{bits}", maxval, np.float64,
                   lambda: eotf((np.arange(1, maxval + 1, dtype=np.float64) - 0.5) / maxval))


@functools.lru_cache(maxsize=1)
def encode_table() -> tuple[np.ndarray, np.ndarray, float]:
    """(value at each point, step to the next, slope below the knee) of the encoding: ENCODE_POINTS
    intervals over the curved segment [KNEE_LINEAR, 1]; the straight one below needs only its slope."""
    grid = KNEE_LINEAR + (1.0 - KNEE_LINEAR) * np.arange(ENCODE_POINTS + 1, dtype=np.float64) / ENCODE_POINTS
    table = cached_table("encode", ENCODE_POINTS + 1, np.float64, lambda: eotf_inverse(grid))
    return table[:-1].astype(np.float32), np.diff(table).astype(np.float32), float(table[0] / KNEE_LINEAR)


def encode(linear) -> np.ndarray:
    """Linear light -> sRGB code values in [0, 1], float32 of the same shape: NaN and values below 0
    become 0, values above 1 (and +inf) become 1. Linear interpolation in a table of the encoding's
    curved segment (within 1e-7 of colour-science), its straight segment by its slope."""
    base, step, slope = encode_table()
    values = np.asarray(linear)
    out = np.empty(values.shape, np.float32)
    flat, codes = values.reshape(-1), out.reshape(-1)
    block = 1 << 18  # float64 scratch of a few MB a block, never of the image's size
    for s in range(0, flat.size, block):
        x = np.clip(np.nan_to_num(flat[s:s + block].astype(np.float64), nan=0.0, posinf=1.0, neginf=0.0), 0.0, 1.0)
        t = np.maximum(x - KNEE_LINEAR, 0.0) * (ENCODE_POINTS / (1.0 - KNEE_LINEAR))
        i = np.minimum(t.astype(np.intp), ENCODE_POINTS - 1)
        curved = base[i] + step[i] * (t - i)
        codes[s:s + block] = np.where(x <= KNEE_LINEAR, x * slope, curved)
    return out
