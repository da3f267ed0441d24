"""``lenslab validate --reference FILE``: warps measured against the user's own render or photograph,
reported as ``lenslab diff`` reports them (one report per warp setting)."""

from __future__ import annotations

import sys
from pathlib import Path

REPORT_FILES = ("reference.json", "reference.md")


def reference_camera(args, image, meta):
    """--reference-camera, else the camera the file records, else --to; posed by --yaw/--pitch/--roll (refused with
    the camera the file records, which has its own orientation)."""
    from lenslab.jobs.warp.cameras import given_pose, lens_camera, refuse_turns
    from lenslab.lenses import Camera, Pose

    h, w = image.shape[:2]
    recorded = meta.get("camera")
    if recorded is not None and not args.reference_camera:
        refuse_turns(given_pose(args), "--reference", args.reference, recorded, "--reference-camera")
        return Camera(recorded.lens.with_size(w, h), recorded.pose) if recorded.size != (w, h) else recorded
    pose = Pose.from_ypr(args.yaw or 0.0, args.pitch or 0.0, args.roll or 0.0, args.eye or (0.0, 0.0, 0.0))
    # a lens spec or calibration file, or an image named as the camera: its lens and the mirror it records (warp --flip)
    cam = lens_camera(args.reference_camera or args.to, (w, h))
    return Camera(cam.lens, Pose(pose.rotation @ cam.pose.rotation, pose.eye))


def source_image(args, ref_cam, settings_count: int):
    """The source to warp: --source (with --from or its recorded camera), else a panorama of --scene
    rendered at the reference camera's eye (the largest of --pano-sizes)."""
    from lenslab.jobs.warp.cameras import source_camera, stored_frame
    from lenslab.io import read
    from lenslab.validate.run import panorama_camera, parse_size

    if args.source:
        image, meta = read(args.source)
        return (*stored_frame(image, meta, source_camera(args.source_spec, meta, image.shape)), args.source)
    from tracer.validate.source import make_source

    size = [parse_size(s) for s in args.pano_sizes.split(",") if s.strip()][-1]
    source = make_source(args.scene, args.integrator, args.max_depth, bool(args.noise_free))
    cam = panorama_camera(ref_cam, size)
    render = source.render(cam, spp=args.spp or 16, seed=args.seed)
    return render.image, cam, f"{args.scene} panorama {size[0]}x{size[1]}"


def run_reference(args) -> int:
    import json

    from lenslab.jobs.diff_arguments import thresholds_from
    from lenslab.errors import UsageError
    from lenslab.jobs.policy import check_output, check_output_dir
    from lenslab.io import read
    from lenslab.metrics.diff_text import diff_text
    from lenslab.validate.reference import against_reference, best
    from lenslab.validate.run import ValidationError, WarpSetting

    try:
        settings = [WarpSetting.parse(s) for s in args.filters.split(",") if s.strip()]
    except ValidationError as exc:
        raise UsageError(str(exc)) from None
    out_dir = Path(args.output)
    check_output_dir(out_dir)
    if out_dir.is_dir():  # an earlier report there is replaced only with --overwrite
        for name in REPORT_FILES:
            check_output(out_dir / name, [args.reference] + ([args.source] if args.source else []), args.overwrite)
    image, meta = read(args.reference)
    ref_cam = reference_camera(args, image, meta)
    src, src_cam, src_name = source_image(args, ref_cam, len(settings))
    rows = against_reference(image, ref_cam, src, src_cam, settings, thresholds_from(args),
                             flip="off" if args.no_flip else "auto", allow_parallax=args.allow_parallax)
    top = best(rows)
    out_dir.mkdir(parents=True, exist_ok=True)
    data = {"reference": args.reference, "reference_camera": ref_cam.lens.spec(),
            "reference_pose": ref_cam.pose.to_dict(), "source": src_name, "source_camera": src_cam.lens.spec(),
            "best": top["label"],
            "settings": [{"label": r["label"], "seconds": r["seconds"], **r["report"].to_dict()} for r in rows]}
    from lenslab.atomic import atomic_write_path

    for name, text in (("reference.json", json.dumps(data, indent=2)),
                       ("reference.md", "\n\n".join(f"## {r['label']}\n\n```\n{diff_text(r['report'], args.reference, r['label'])}\n```"
                                                    for r in rows))):
        with atomic_write_path(out_dir / name, overwrite=args.overwrite) as tmp:
            Path(tmp).write_text(text + "\n")
    for r in rows:
        rep = r["report"]
        print(f"{r['label']:<22} RMS {rep.rms_error:.6g}  mean {rep.mean_error:.6g}  max {rep.max_error:.6g}  "
              f"PSNR {rep.psnr:.4g} dB" + (f"  FLIP {rep.flip:.4g}" if rep.flip is not None else "")
              + f"  {rep.verdict_name}")
    print(diff_text(top["report"], args.reference, f"{src_name} warped ({top['label']})"))
    print(f"report written to {out_dir}/reference.md", file=sys.stderr)
    return 0
