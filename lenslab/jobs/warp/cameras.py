"""The cameras of ``lenslab warp``: the source's (--from, the file's own, or a 2:1 panorama), the output's
(--to at --size, posed by --yaw/--pitch/--roll or --look-at, --eye), its default size, --autoscale."""

from __future__ import annotations

import sys


def parse_vector(text: str, what: str) -> tuple[float, float, float]:
    import math

    from lenslab.errors import WarpError

    try:
        v = tuple(float(p) for p in (text if isinstance(text, (tuple, list)) else str(text).split(",")))
    except ValueError:
        v = ()
    if len(v) != 3 or not all(math.isfinite(c) for c in v):
        raise WarpError(f"{what} {text!r} must be three numbers X,Y,Z, e.g. 0,0,1")
    return v


def source_camera(spec: str | None, meta: dict, shape: tuple[int, ...]):
    """The source camera: --from, else the file's camera, else equirect for a 2:1 image."""
    from lenslab.errors import WarpError
    from lenslab.lenses import Camera

    h, w = shape[:2]
    if spec:
        from lenslab.lenses.spec_kinds import exif_photo, is_auto, is_exif

        if is_auto(spec) and not (spec.strip().lower() == "auto" and meta.get("camera") is not None):
            from lenslab.lenses.lensfun.match import auto_spec

            spec = auto_spec(spec, meta.get("path", ""))  # the lens the photo's metadata names
            _note(f"source lens from the file's metadata: {spec}")
        elif is_auto(spec):  # auto: the camera the file records
            spec = None
        elif is_exif(spec) and exif_photo(spec) is None:  # exif: the pinhole of this photo's focal length
            from lenslab.io.exif_orientation import stored_size
            from lenslab.lenses.exif_view import exif_view

            view = exif_view(meta.get("path", ""), (w, h), stored_size(meta.get("path", ""), (w, h)))
            spec = view.spec
            _note(f"source lens from the file's EXIF: {view.describe()}")
    if spec:
        return lens_camera(spec, (w, h))
    cam = meta.get("camera")
    if cam is not None:
        if cam.size != (w, h):
            return Camera(cam.lens.with_size(w, h), cam.pose)
        return cam
    if w == 2 * h:
        return Camera.from_spec("equirect", (w, h))
    raise WarpError(f"{meta.get('path', 'the input')}: {w}x{h} is not a 2:1 panorama and the file records no "
                    f"camera; say what it is with --from SPEC (e.g. {exif_hint(meta, (w, h))})")


def lens_camera(spec: str, size: tuple[int, int], own_size: bool = False):
    """The unturned camera of ``--from SPEC`` at ``size``: its lens, or for an image that records a mirrored camera
    (``lenslab warp --flip`` wrote it) its lens and that mirror (:attr:`lenslab.lenses.Pose.mirror`), not its turn:
    its pixels show the world mirrored, which no turn undoes, so its lens alone would read it back mirrored.
    ``own_size``: an image at its own size, not ``size`` (which a lens spec or a calibration file takes)."""
    from lenslab.lenses import Camera, Pose
    from lenslab.lenses.core.pose import mirror_matrix

    from lenslab.calibfiles import split_pick

    view = recorded_view(spec)  # (an image read once, for its lens and its mirror)
    if view is None or split_pick(spec)[1] not in (None, "0"):  # (an image's one camera is #0: another, refused)
        return Camera.from_spec(spec, size)
    lens = view.lens if own_size or tuple(size) == view.size else view.lens.with_size(*size)
    return Camera(lens, Pose(mirror_matrix(view.pose.mirror)))


def _note(text: str) -> None:
    """A note of the file being warped: the command prints it led by that file's name, once per file, in a batch too
    (``lenslab warp: note: IMG_1.jpg: ...``)."""
    import warnings

    warnings.warn(text, UserWarning, stacklevel=3)


def exif_hint(meta: dict, size: tuple[int, int]) -> str:
    """The ``--from`` a photo's EXIF gives (``--from exif``, its field of view), else a fisheye's example."""
    from lenslab.errors import LenslabError
    from lenslab.io.exif_orientation import stored_size
    from lenslab.lenses.exif_view import exif_view

    try:
        view = exif_view(meta.get("path", ""), size, stored_size(meta.get("path", ""), size), crop_note=False)
    except (LenslabError, OSError):
        return "--from fisheye:fov=180"
    return f"--from exif: its EXIF's 35 mm equivalent {view.focal35:.4g} mm gives {view.spec}"


def stored_frame(image, meta: dict, src):
    """``image`` and ``src`` in the stored frame of a photo read turned as its EXIF orientation says
    (:mod:`lenslab.io.exif_orientation`) where the source lens describes the sensor's pixels as stored
    (:attr:`~lenslab.lenses.core.base.Lens.sensor_frame`: a calibration, a camera file); else as they are."""
    orientation = meta.get("exif_orientation", 1)
    if orientation == 1 or not src.lens.sensor_frame:
        return image, src
    import numpy as np

    from lenslab.io.exif_orientation import turn
    from lenslab.lenses import Camera

    image = np.ascontiguousarray(turn(image, {6: 8, 8: 6}.get(orientation, orientation)))  # the inverse turn
    return image, Camera(src.lens.with_size(image.shape[1], image.shape[0]), src.pose)


def source_rows(lens) -> int:
    """The rows of 180 degrees at the source's angular resolution (:meth:`~lenslab.lenses.core.base.Lens.
    pixels_per_degree`), from which :func:`default_size` makes the output's size: an equirect's rows, twice a
    cube map's faces in any layout."""
    return max(1, round(180.0 * lens.pixels_per_degree()))


#: an output without --size holds at most this many times the source's pixels: a whole sphere from a 180-degree
#: fisheye, or a 360 x 90 degree strip of tiles, at their own pixels per degree, takes twice their pixels; a
#: 60-degree photo of 4000 x 3000 into a whole equirect at its own 64 pixels per degree would take 266 million
DEFAULT_PIXELS_FACTOR = 2.0


def default_output_size(spec: str, lens) -> tuple[int, int]:
    """The output's size without --size: the source ``lens``'s pixels per degree (:func:`default_size` of
    :func:`source_rows`), at most :data:`DEFAULT_PIXELS_FACTOR` times its pixels. A size limited so is said
    in a note that gives the --size keeping the source's resolution, or, where that size is more than an image
    can be (a band of a hundredth of a degree), says so."""
    import math
    import warnings

    from lenslab.errors import LensError
    from lenslab.lenses.core.base import check_size

    probe = _probe_lens(spec)
    rows, full, valid = target_rows(probe, source_rows(lens)), None, False
    eyes = _eyes(probe) / _eyes(lens)  # a stereo frame of a mono source: two views, each may take the limit
    limit = DEFAULT_PIXELS_FACTOR * lens.width * lens.height * eyes
    try:
        full = default_size(spec, rows)
        valid = bool(check_size(*full))
    except LensError:  # a cube map's frame cannot even be made at that many rows
        default_size(spec, 256)  # (a spec at fault says so)
    if valid and full[0] * full[1] <= limit:
        return full
    base = rows if full else 256  # (else the lens's shape at 256 rows: its pixels grow as the square of its rows)
    w, h = full or default_size(spec, base)
    size = default_size(spec, max(1, min(rows, math.floor(base * math.sqrt(limit / (w * h))))))
    ppd = f"the source's {lens.pixels_per_degree():.3g} pixels per degree"
    keep = (f"--size {full[0]}x{full[1]} keeps {ppd}" if valid else
            f"{ppd} would make it{f' {w} x {h},' if full else ''} more than an image can be: give --size WxH for "
            "another size")
    each = " per eye" if eyes > 1 else ""
    warnings.warn(f"without --size the output is {size[0]} x {size[1]}, at most {DEFAULT_PIXELS_FACTOR:g} times the "
                  f"source's pixels{each}; {keep}", UserWarning, stacklevel=2)
    return size


#: rows of 180 degrees at which an output lens is made to be measured (10 rows a degree: a field of whole degrees
#: takes whole rows)
PROBE_ROWS = 3600


def _probe_lens(spec: str):
    """The output lens ``spec`` made at :data:`PROBE_ROWS` rows of 180 degrees, to be measured; None for a spec that
    cannot be made (it says so where its size is made)."""
    from lenslab.errors import LensError
    from lenslab.lenses.registry import make_lens

    try:
        return make_lens(spec, default_size(spec, PROBE_ROWS))
    except (LensError, ValueError, ZeroDivisionError):
        return None


def _eyes(lens) -> int:
    """The eyes a lens shows: 2 for a stereo frame's pieces, else 1 (also for no lens)."""
    if lens is None:
        return 1
    return max(1, len({p.eye for p in (lens.pieces() or ())} - {None}))


def target_rows(probe, rows: int) -> int:
    """The rows to give :func:`default_size` so that the output lens (``probe``, made by :func:`_probe_lens`) has the
    resolution of ``rows`` rows over 180 degrees, measured as a source's is
    (:meth:`~lenslab.lenses.core.base.Lens.pixels_per_degree`: its first piece's rows over the degrees its middle
    column spans): ``rows`` for a 180-degree fisheye, a whole equirect or a cube map; half for a 90-degree
    perspective view or fisheye, 2/3 for a 120-degree one. Where the piece's middle row is coarser in angle than its
    column (a cylindrical panorama's 360 degrees, a barrel's band), the row's resolution is the one kept: no line
    through the middle is coarser than the source. ``rows`` itself where there is no probe."""
    import math

    from lenslab.errors import LensError

    if probe is None:
        return rows
    try:
        from lenslab.lenses.core.resolution import row_pixels_per_degree

        ppd = min(probe.pixels_per_degree(), row_pixels_per_degree(probe))
    except (LensError, ValueError, ZeroDivisionError):
        return rows
    if not (math.isfinite(ppd) and ppd > 0):
        return rows
    return max(1, round(rows * PROBE_ROWS / (180.0 * ppd)))


def default_size(spec: str, src_h: int, nested: bool = False) -> tuple[int, int]:
    """The output's size without --size: ``src_h`` rows of 180 degrees (:func:`source_rows`) in the lens's shape.
    ``nested``: ``spec`` is the base model of another's (``stereo:base=...``), which names a model, never a file."""
    from lenslab.calibfiles import is_camera_file
    from lenslab.lenses.registry import make_lens, parse_spec

    if is_camera_file(spec):  # a calibrated camera: the size it was calibrated at
        lens = make_lens(spec)
        return lens.width, lens.height
    name, values = parse_spec(spec)
    if name == "stereo":  # two eyes of the base's default frame, side by side or one above the other
        base = values.pop("base", "equirect")
        layout = values.pop("layout", "sbs")
        w, h = default_size(_base_spec(base, values), src_h, nested=True)
        return (2 * w, h) if layout == "sbs" else (w, 2 * h)
    from lenslab.lenses.registry import lens_class

    cls = lens_class(name, None if nested else spec)
    own = {p.name for p in cls.params}
    if "base" in own and values.get("base"):  # a bend or optics over a base model, at its size: the base's frame
        return default_size(_base_spec(values["base"], {k: v for k, v in values.items() if k not in own}), src_h,
                            nested=True)
    if hasattr(cls, "default_frame"):  # square pieces of whole pixels (cube faces, tiles), an equirect's ranges, a
        # lensfun profile's calibration sensor
        probe = cls.probe_size(values) if hasattr(cls, "probe_size") else (src_h, src_h)  # (a size its grid splits)
        return make_lens(spec, probe).default_frame(src_h)

    aspect = getattr(cls, "frame_aspect", None)  # the frame a model fills (width / height)
    if aspect:
        return max(1, round(src_h * aspect)), src_h
    return src_h, src_h


def _base_spec(base: str, values: dict) -> str:
    """The spec of a base model with the values passed through to it."""
    return base + "".join(f",{k}={v}" for k, v in values.items()).replace(",", ":", 1)


def note_size(lens) -> None:
    """The lens's note on the image size it was given (:meth:`~lenslab.lenses.core.base.Lens.size_note`, e.g. a cube
    map whose faces are not square), as a warning: the command prints it once as its note."""
    note = lens.size_note()
    if note:
        import warnings

        warnings.warn(note, UserWarning, stacklevel=2)


def recorded_view(spec):
    """The camera, lens and pose, that an image named as a lens records (``--to render.exr``: an EXR that
    ``tracer render`` or ``lenslab warp`` wrote), or None for a lens spec or a calibration file."""
    from lenslab.calibfiles import image_camera, is_camera_file, split_pick

    if not spec or not is_camera_file(spec):
        return None
    return image_camera(split_pick(spec)[0])


def given_pose(args, *flags: str) -> list[str]:
    """The pose options among ``flags`` (default ``--yaw``, ``--pitch``, ``--roll``) given on the command line, whatever
    their value: they default to None, so ``--yaw 0`` is seen as given as ``--yaw 10`` is."""
    flags = flags or ("--yaw", "--pitch", "--roll")
    return [flag for flag in flags if getattr(args, flag.lstrip("-").replace("-", "_"), None) is not None]


def check_view_pose(spec, pose_options: list[str]):
    """``--to IMAGE`` takes the view the image records, its orientation too: options that would turn it are a
    usage error (which way they meant, the render's or the world's, cannot be told). Returns the view or None."""
    view = recorded_view(spec)
    if view is not None:
        refuse_turns(pose_options, "--to", spec, view)
    return view


def refuse_turns(flags: list[str], option: str, path, view, spec_option: str | None = None) -> None:
    """The usage error of options ``flags`` that would turn the view an image records (``option path``: ``--to
    render.exr``), naming its orientation and the lens spec to give (as ``spec_option``, default ``option``) to turn
    that lens another way; nothing when none is given."""
    if not flags:
        return
    from lenslab.errors import UsageError

    yaw, pitch, roll = (round(a, 6) + 0.0 for a in view.pose.ypr)  # (1e-16 of a matrix's rounding: 0)
    what = " or ".join(dict.fromkeys(VIEW_CHANGES.get(flag, "turn that lens another way") for flag in flags))
    mirror = f"mirrored {view.pose.mirror}, then " if view.pose.mirror else ""  # (a view warp --flip made)
    # (an option that is no turn mirrors or scales the file's own view: the options that give that view go with it)
    turns = "" if any(flag not in VIEW_CHANGES for flag in flags) else view_turns(view.pose)
    raise UsageError(f"{'/'.join(flags)}: {option} {path} takes the view that file records, its lens and its "
                     f"orientation ({mirror}yaw {yaw:g}, pitch {pitch:g}, roll {roll:g}); to {what}, give "
                     f"it as a spec: {spec_option or option} {view.lens.spec()}{turns}")


def view_turns(pose) -> str:
    """The ``--yaw``, ``--pitch``, ``--roll`` (and a mirrored view's ``--flip``) that give ``pose``'s orientation from a
    lens spec, those that are not 0, each led by a space. ``--flip`` mirrors the rays after the turns
    (``M R_flags``), so a pose recorded as a mirror then a turn (``R = turn M``) has the turns of ``M R``."""
    from lenslab.lenses.core.pose import matrix_to_ypr, mirror_matrix

    letter = pose.mirror
    angles = matrix_to_ypr(mirror_matrix(letter) @ pose.rotation) if letter else pose.ypr
    named = [f" --{name} {round(a, 9) + 0.0:.12g}" for name, a in zip(("yaw", "pitch", "roll"), angles)
             if round(a, 9) != 0]
    return "".join(named) + (f" --flip {letter}" if letter else "")


#: what the options other than turns (and --rotation-order, the order of turns) would do to a view an image records:
#: each makes the output another view than the file's, so :func:`refuse_turns` names the spec to give instead
VIEW_CHANGES = {"--flip": "mirror that lens's rays", "--autoscale": "scale that lens's field of view"}


def check_turn_order(args) -> None:
    """``--rotation-order`` orders the turns --yaw/--pitch/--roll give: without any of them it changes nothing, a
    usage error as every option that cannot apply (``--look-at`` is a direction, in no order)."""
    if getattr(args, "rotation_order", None) is None or given_pose(args):
        return
    from lenslab.errors import UsageError

    look = " (--look-at gives a direction, in no order)" if getattr(args, "look_at", None) is not None else ""
    raise UsageError(f"--rotation-order {args.rotation_order} orders the turns of --yaw, --pitch and --roll, and none "
                     f"is given{look}: it would change nothing; drop it, or give the turns it orders")


def records_place(src, meta: dict) -> bool:
    """Whether the source camera's pose is the one its file records (no --from replaced the file's camera) and
    places it in a world: lenslab records every output's camera, a photographed panorama's at the origin, so
    an eye at the origin places nothing."""
    import numpy as np

    camera = meta.get("camera")
    return camera is not None and src.pose is camera.pose and bool(np.any(np.asarray(camera.pose.eye) != 0))


def place_source(spec, src, placed: bool, eye=None):
    """``--to IMAGE`` (an image that records its camera) from a source that records no place (``placed`` False:
    a photographed panorama, or one lenslab made of it): the source as seen from the view's eye (``eye``, the
    text of --eye, else the image's), the light arriving there. Any other source as it is."""
    view = recorded_view(spec)
    if view is None or placed:
        return src
    import numpy as np

    from lenslab.lenses import Camera, Pose

    at = parse_vector(eye, "--eye") if eye else view.pose.eye
    return Camera(src.lens, Pose(src.pose.rotation, np.asarray(at, dtype=np.float64)))


def output_camera(args, src, size: tuple[int, int]):
    """The output camera: its lens at ``size``, its pose in the world frame (the source's pose, if its
    file records one, is accounted for by the warp), its eye at the source's unless --eye says otherwise.

    ``--to IMAGE`` (an image that records its camera) is the view of that image: its lens, orientation and eye
    (a source placed in the same world elsewhere is then refused for parallax; one that records no place is
    taken as seen from the image's eye by :func:`place_source`)."""
    import numpy as np

    from lenslab.lenses import Camera, Pose, make_lens

    view = recorded_view(args.to)
    if view is not None:  # (the image read once for its lens and its pose)
        lens = view.lens if tuple(size) == view.size else view.lens.with_size(*size)
        eye = parse_vector(args.eye, "--eye") if args.eye else tuple(view.pose.eye)
        return Camera(lens, Pose(view.pose.rotation, np.asarray(eye, dtype=np.float64)))
    lens = make_lens(args.to, size)
    eye = parse_vector(args.eye, "--eye") if args.eye else tuple(src.pose.eye)
    if args.look_at:
        d = np.asarray(parse_vector(args.look_at, "--look-at"), dtype=np.float64)
        if np.hypot(d[0], d[2]) <= 1e-12 * np.linalg.norm(d) and d[1] != 0:
            # straight up or down, where "up" gives no direction: the pose --pitch 90 (or -90) gives,
            # the top of the image towards -z (up) or +z (down)
            return Camera(lens, Pose.from_ypr(0.0, 90.0 if d[1] > 0 else -90.0, 0.0, eye))
        return Camera(lens, Pose.look_at(eye, np.add(eye, d)))
    yaw, pitch, roll = (getattr(args, k, None) or 0.0 for k in ("yaw", "pitch", "roll"))  # (None: not given)
    return Camera(lens, Pose.from_ypr(yaw, pitch, roll, eye, getattr(args, "rotation_order", None) or "ypr"))


def autoscale_camera(src, dst, mode="fill", samples=1, quiet=False, verbose=False):
    """Hook for --autoscale: the output camera scaled to fit the source (provided by lenslab.fit)."""
    from lenslab.errors import WarpError

    try:
        from lenslab.fit.autoscale import autoscale_camera as fit_autoscale
    except ImportError:
        raise WarpError("--autoscale is not available in this installation (lenslab.fit.autoscale is missing); "
                        "give the output lens's parameters explicitly") from None
    return fit_autoscale(src, dst, mode, samples,
                         report=None if quiet else (lambda line: print(f"lenslab warp: {line}", file=sys.stderr)),
                         verbose=verbose)
