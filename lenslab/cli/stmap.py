"""Write the map of a lens-to-lens warp as an ST map, for Nuke, Fusion, After Effects or any compositor.

Each pixel of the map (the size of the output, --size) holds where that output pixel's centre reads the
source, in Nuke's STMap convention: R = s = x / W and G = t = 1 - y / H of the source position (pixel
centres at +0.5, t growing upward), A = 1 where the output pixel has a ray that the source sees, else 0.
The map is a 32-bit float EXR. --from is the lens the footage was shot with, --to the lens you want: a
map from a distorted lens to a perspective one undistorts, the other way round it distorts (to match CG
to a plate). Apply it with Nuke's STMap node, or with 'lenslab warp IMAGE --stmap MAP'.

examples:
  lenslab stmap --from fisheye:fov=180,mapping=equisolid --to perspective:fov=100 --size 1920x1080 -o undistort.exr
  lenslab stmap --from perspective:fov=100 --to fisheye:fov=180,mapping=equisolid --size 2048x2048 \\
      --source-size 1920x1080 -o distort.exr
  lenslab stmap --from exif:photo=IMG_0042.jpg --to equirect --size 4096x2048 -o photo-to-pano.exr
  lenslab stmap --from dual-fisheye:fov=190 --source-size 5760x2880 --to equirect --size 5760x2880 -o stitch.exr
"""

from __future__ import annotations

import argparse
import sys

from lenslab.jobs.arguments import finite_float, image_size


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("-o", "--output", required=True, metavar="MAP.exr", help="the ST map to write (EXR)")
    parser.add_argument("--from", dest="source", required=True, metavar="SPEC",
                        help="lens of the source footage, e.g. fisheye:fov=180 (see 'lenslab lenses'); "
                             "exif:photo=PHOTO: the pinhole of a photo's EXIF 35 mm equivalent focal length, "
                             "as 'lenslab warp PHOTO --from exif' takes it")
    parser.add_argument("--to", required=True, metavar="SPEC", help="lens of the output, e.g. perspective:fov=90")
    parser.add_argument("--size", metavar="WxH", type=image_size,
                        help="output (and map) size in pixels (default, with --to IMAGE that records its camera: "
                             "the size it was rendered at; else needed)")
    parser.add_argument("--source-size", metavar="WxH", type=image_size,
                        help="size of the source footage (default: the photo's as shown for exif:photo=PHOTO, "
                             "the image's own for --from IMAGE, else --size)")
    parser.add_argument("--yaw", type=finite_float, help="turn the output camera right, degrees (default 0)")
    parser.add_argument("--pitch", type=finite_float, help="turn the output camera up, degrees (default 0)")
    parser.add_argument("--roll", type=finite_float, help="turn the output camera about its axis, degrees (default 0)")
    parser.add_argument("--overwrite", action="store_true", help="replace an existing map")
    parser.add_argument("--quiet", "-q", action="store_true", help="no progress bar and no summary")


def run(args: argparse.Namespace) -> int:
    from pathlib import Path

    from lenslab.errors import UsageError
    from lenslab.jobs.policy import check_output
    from lenslab.lenses import Camera, Pose, make_lens
    from lenslab.stmap import st_map, write_st_map

    out = Path(args.output)
    if out.suffix.lower() != ".exr":
        raise UsageError(f"{out}: an ST map is written as a float EXR; name it .exr")
    check_output(out, [], args.overwrite)
    from lenslab.jobs.warp.cameras import check_view_pose, given_pose

    view = check_view_pose(args.to, given_pose(args))
    size = args.size or (tuple(view.size) if view is not None else None)  # --to render.exr: its own size
    if size is None:
        raise UsageError("give the map's size: --size WxH (only --to IMAGE, an image that records its camera, has "
                         "its own)")
    from lenslab.jobs.warp.cameras import lens_camera

    given = args.source_size or photo_size(args.source)  # else --from IMAGE: the image's own size, which the map reads
    src = lens_camera(args.source, given or size, own_size=given is None)  # (an image's mirror kept)
    src_size = (src.lens.width, src.lens.height)
    dst = Camera(make_lens(args.to, size), Pose(view.pose.rotation) if view is not None else  # --to IMAGE: its view
                 Pose.from_ypr(args.yaw or 0.0, args.pitch or 0.0, args.roll or 0.0))
    from lenslab.jobs.warp.cameras import note_size

    note_size(dst.lens)  # a cube map at a size off its layout: one note
    from lenslab.jobs.progress import RowBar

    bar = RowBar(out.name) if not args.quiet and sys.stderr.isatty() else None
    try:
        if bar is not None:
            bar.start(size[1])
        st = st_map(src, dst, progress=bar)
        if bar is not None:  # the full bar names the writing, should it outlast the patience
            bar.status(f"writing {out.name}")
        write_st_map(out, st, overwrite=args.overwrite,
                     attributes={"lenslab:stmap": f"from {src.lens.spec()} {src_size[0]}x{src_size[1]} "
                                                   f"to {dst.lens.spec()} {size[0]}x{size[1]}"})
    finally:
        if bar is not None:
            bar.close()
    if not args.quiet:
        seen = float(st[..., 3].mean())
        print(f"wrote {out}: {size[0]}x{size[1]} ST map, {100 * seen:.1f}% of pixels see the source",
              file=sys.stderr)
    return 0


def photo_size(spec: str):
    """The size as shown of the photo an ``exif:photo=PHOTO`` source names, else None."""
    from lenslab.lenses.exif_view import exif_photo, is_exif

    if not is_exif(spec) or exif_photo(spec) is None:
        return None
    from lenslab.io.exif_orientation import shown_size

    size = shown_size(exif_photo(spec))  # from its header: the photo (and its gain map) is not decoded
    if size is None:
        from lenslab.io import read

        size = tuple(read(exif_photo(spec))[1]["size"])
    return size
