#!/usr/bin/env python3
"""Coverage-guided fuzzing (atheris, libFuzzer) of every image reader and calibration-file parser.

    python tools/fuzz/fuzz.py --all --seconds 120          # every target for 2 minutes each, one summary
    python tools/fuzz/fuzz.py image:tiff -max_total_time=600   # one target; libFuzzer's own flags after it
    python tools/fuzz/fuzz.py --list                        # the targets

The targets come from the registries: ``image:NAME`` for each readable format of ``lenslab.io.registry`` (through
``lenslab.io.read``, budget included) and ``camera:NAME`` for each format of ``lenslab.calibfiles``; ``exif:block``
for the Exif block parser (a JPEG's APP1 payload, a PNG's eXIf chunk, a TIFF's IFDs: :mod:`lenslab.io.exif`) and
``exif:exr-header`` for the camera and Exif tags read from an EXR's header attributes (``lenslab.camera``,
``Exif:FocalLength``... of any type the bindings give: text, numbers, arrays, boxes, built from the input by
atheris' data provider). Each starts from a seed corpus of valid files written by lenslab (an Exif block for the
``exif:`` targets), kept in ``tools/fuzz/corpus/TARGET``, made on first use, not committed. An input passes when it
reads, or fails with a lenslab error or OSError whose message is one line; any other exception, a multi-line
message, a crash, an allocation beyond 2 GB (``-rss_limit_mb``) or a hang beyond 20 s (``-timeout``) is a finding,
saved by libFuzzer as ``crash-*``/``oom-*``/``timeout-*`` in ``tools/fuzz/findings/TARGET``.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]


def targets() -> list[str]:
    sys.path.insert(0, str(REPO))
    from lenslab import calibfiles
    from lenslab.io.registry import formats

    return ([f"image:{n}" for n, f in formats().items() if f.readable]
            + [f"camera:{n}" for n in calibfiles.FORMATS] + list(EXIF_TARGETS))


#: the targets of metadata parsers that take bytes or header values rather than a file
EXIF_TARGETS = ("exif:block", "exif:exr-header")


def seed(target: str, folder: Path) -> None:
    """Write a few valid files of ``target`` into ``folder``."""
    sys.path.insert(0, str(REPO))
    from tests.io.test_hostile_mutations import camera_seeds, image_seeds

    folder.mkdir(parents=True, exist_ok=True)
    kind, name = target.split(":")
    if kind == "exif":
        from lenslab.io.exif.ifd import build

        block = build({"Make": "Acme", "Model": "One", "FocalLength": 6.81, "FocalLengthIn35mmFilm": 26,
                       "FocalPlaneXResolution": 400, "PixelXDimension": 4000, "LensModel": "Wide 4.2"})
        (folder / "seed").write_bytes(block if name == "block" else b"\x01" * 64 + block)
        return
    with tempfile.TemporaryDirectory() as d:
        if kind == "image":
            data = image_seeds(Path(d))[name]
        else:
            data = camera_seeds(Path(d))[name][1]
    (folder / "seed").write_bytes(data)


def suffix(target: str) -> str:
    kind, name = target.split(":")
    if kind == "exif":
        return ".bin"
    if kind == "image":
        from lenslab.io.registry import formats

        return formats()[name].extensions[0]
    return {"opencv": ".yaml", "kalibr": ".yaml", "colmap": ".txt", "ocam": ".txt", "toml": ".toml"}.get(name, ".txt")


#: names a function uses when it builds a numba kernel: numba compiles its inner functions from their
#: bytecode, which atheris' coverage hooks would make uncompilable
_NUMBA = {"njit", "jit", "numba", "vectorize", "guvectorize", "cfunc", "stencil"}


def _builds_kernels(code) -> bool:
    return bool(_NUMBA & set(code.co_names)) or any(
        _builds_kernels(c) for c in code.co_consts if hasattr(c, "co_names"))


def instrument(atheris, modules) -> None:
    """Add coverage hooks to the functions and methods defined in ``modules``, kernel builders left out."""
    import inspect

    for module in modules:
        for obj in list(vars(module).values()):
            if getattr(obj, "__module__", None) != module.__name__:
                continue
            funcs = [obj] if inspect.isfunction(obj) else [
                f for f in vars(obj).values() if inspect.isfunction(f)] if inspect.isclass(obj) else []
            for func in funcs:
                if not _builds_kernels(func.__code__):
                    atheris.instrument_func(func)


def _header_value(fdp):
    """One EXR attribute value of a type OpenEXR's bindings give: text, int, float, a numpy array (a double, a
    vector, a matrix), a box (a pair of arrays), a list of floats (chromaticities), None."""
    import numpy as np

    kind = fdp.ConsumeIntInRange(0, 7)
    if kind == 0:
        return fdp.ConsumeUnicodeNoSurrogates(fdp.ConsumeIntInRange(0, 4096))
    if kind == 1:
        return fdp.ConsumeInt(8)
    if kind == 2:
        return fdp.ConsumeRegularFloat() if fdp.ConsumeBool() else fdp.ConsumeFloat()
    if kind == 3:
        return np.array([fdp.ConsumeFloat() for _ in range(fdp.ConsumeIntInRange(0, 16))], np.float64)
    if kind == 4:
        return (np.array([fdp.ConsumeInt(4), fdp.ConsumeInt(4)]), np.array([fdp.ConsumeInt(4), fdp.ConsumeInt(4)]))
    if kind == 5:
        return [fdp.ConsumeFloat() for _ in range(fdp.ConsumeIntInRange(0, 8))]
    if kind == 6:
        return fdp.ConsumeBytes(fdp.ConsumeIntInRange(0, 256))
    return None


def exif_one(atheris, target: str, data: bytes) -> None:
    """``exif:block``: ``data`` read as an Exif block; ``exif:exr-header``: a header of attributes built from it read
    for its Exif tags, its camera (``lenslab.camera``) and its lens (``--from exif``). An input passes when it gives
    tags, a note or a one-line error."""
    import warnings

    if target == "exif:block":
        from lenslab.io.exif.ifd import Damaged
        from lenslab.io.exif.sources import TooLarge, _of_bytes

        try:
            _of_bytes(data)
        except (Damaged, TooLarge) as exc:
            if "\n" in str(exc) or len(str(exc)) > 600:
                raise AssertionError(f"a message of {len(str(exc))} characters over several lines") from exc
        return
    from lenslab.exif_tags import EXR_FALLBACK, TAGS, exr_tags
    from lenslab.io import _camera
    from lenslab.io.exr import plain_value

    fdp = atheris.FuzzedDataProvider(data)
    names = ["lenslab.camera"] + [t.exr for t in TAGS.values()] + list(EXR_FALLBACK.values())
    header = {}
    for _ in range(fdp.ConsumeIntInRange(0, 12)):
        header[fdp.PickValueInList(names)] = _header_value(fdp)
    if fdp.ConsumeBool():  # a camera TOML, its mirror and turn from the input
        mirror = fdp.ConsumeUnicodeNoSurrogates(fdp.ConsumeIntInRange(0, 64))
        header["lenslab.camera"] = (f'mirror = "{mirror}"\nyaw = {fdp.ConsumeFloat()!r}\n'
                                    f'[lens]\nmodel = "perspective"\nsize = [64, 48]\nfov = 60.0\n')
    exr_tags(header)
    with warnings.catch_warnings(record=True) as notes:
        warnings.simplefilter("always")
        _camera("in.exr", plain_value(header.get("lenslab.camera")))  # (as the reader gives it)
    for note in notes:
        if "\n" in str(note.message) or len(str(note.message)) > 600:
            raise AssertionError(f"a note of {len(str(note.message))} characters over several lines")


def fuzz(target: str, argv: list[str]) -> None:
    import atheris

    sys.path.insert(0, str(REPO))
    import importlib
    import pkgutil
    import warnings

    import lenslab.calibfiles
    import lenslab.inputs
    import lenslab.io
    from lenslab.calibfiles import read_lenses
    from lenslab.errors import LenslabError
    from lenslab.io import read

    # the readers import their codecs lazily: import them all first, then instrument their functions
    # (atheris' import hook misses modules an editable install loads through its own finder, and
    # uninstrumented code gives the fuzzer no coverage to follow)
    modules = [lenslab.io, lenslab.inputs, lenslab.calibfiles]
    import lenslab.exif_tags
    import lenslab.lenses.core.camera
    import lenslab.lenses.core.pose

    extra = [lenslab.exif_tags, lenslab.lenses.core.camera, lenslab.lenses.core.pose]
    for package in list(modules):
        for info in pkgutil.walk_packages(package.__path__, package.__name__ + "."):
            modules.append(importlib.import_module(info.name))
    instrument(atheris, modules + extra)
    warnings.simplefilter("ignore")
    kind = target.split(":")[0]
    tmp = Path(tempfile.mkdtemp(prefix="lenslab-fuzz-")) / f"input{suffix(target)}"
    import atexit
    import shutil

    atexit.register(shutil.rmtree, tmp.parent, True)  # atheris ends the process: remove the scratch folder then

    def one(data: bytes) -> None:
        try:
            if target in EXIF_TARGETS:
                exif_one(atheris, target, data)
                return
            tmp.write_bytes(data)
            read(tmp) if kind == "image" else read_lenses(str(tmp))
        except (LenslabError, OSError) as exc:
            if "\n" in str(exc) or len(str(exc)) > 600:
                raise AssertionError(f"a message of {len(str(exc))} characters over several lines") from exc

    atheris.Setup([sys.argv[0], *argv], one)
    atheris.Fuzz()


def main() -> int:
    args = sys.argv[1:]
    if not args or args[0] in ("-h", "--help"):
        print(__doc__)
        return 0
    if args[0] == "--list":
        print("\n".join(targets()))
        return 0
    if args[0] == "--seed":  # (in its own process: the fuzzing process must import lenslab instrumented)
        seed(args[1], Path(args[2]))
        return 0
    if args[0] == "--all":
        seconds = int(args[args.index("--seconds") + 1]) if "--seconds" in args else 60
        failed = []
        for t in targets():
            found = HERE / "findings" / t.replace(":", "-")
            found.mkdir(parents=True, exist_ok=True)
            before = set(found.iterdir())
            done = subprocess.run([sys.executable, __file__, t, f"-max_total_time={seconds}", "-rss_limit_mb=2048",
                                   "-timeout=20", f"-artifact_prefix={found}/"], capture_output=True, text=True)
            new = sorted(set(found.iterdir()) - before)
            lines = done.stderr.splitlines()
            cov = [line.split("cov:")[1].split()[0] for line in lines if "cov:" in line][-1:] or ["?"]
            runs = [line for line in lines if line.startswith("Done ")][-1:] or [
                "stopped by a finding" if new else "did not run"]
            print(f"{t:16s} exit {done.returncode}  coverage {cov[0]:>5s}  {runs[0]}  findings: {len(new)}")
            if done.returncode and not new:  # the fuzzer itself failed (no seed corpus, no atheris...)
                failed.append(t)
                print("   " + "\n   ".join(done.stderr.strip().splitlines()[-6:]))
            if new:
                failed.append(t)
                print("   " + "\n   ".join(str(p) for p in new))
                print("   " + "\n   ".join(done.stderr.strip().splitlines()[-12:]))
        return 1 if failed else 0
    target, rest = args[0], args[1:]
    corpus = HERE / "corpus" / target.replace(":", "-")
    if not corpus.is_dir() or not any(corpus.iterdir()):
        subprocess.run([sys.executable, __file__, "--seed", target, str(corpus)], check=True)
    fuzz(target, rest + [str(corpus)])
    return 0


if __name__ == "__main__":
    sys.exit(main())
