"""The plain-text report of :func:`lenslab.metrics.diff.diff_images`, laid out like idiff's."""

from __future__ import annotations

import math


def _g(v) -> str:
    if v is None:
        return "-"
    if isinstance(v, float) and not math.isfinite(v):
        return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf")
    return f"{v:.6g}"


def diff_text(report, first: str, second: str) -> str:
    """Lines a user reads: what was compared, the per-channel table, idiff's summary and the verdict."""
    r = report
    lines = [f'Comparing "{first}" and "{second}"',
             f"  {r.width} x {r.height}, channels {','.join(r.channels)}: {r.pixels} pixels compared"
             + (f", {r.masked_out} left out (not fully covered in both)" if r.masked_out else "")
             + (f", {r.nonfinite} with NaN or infinity in one image only (counted as failing)" if r.nonfinite else "")]
    head = f"  {'channel':<8}{'mean abs':>12}{'RMS abs':>12}{'max abs':>12}  {'at (x, y)':<12}{'mean rel':>12}{'RMS rel':>12}{'max rel':>12}"
    lines.append(head)
    for c in r.per_channel:
        at = f"({c.max_at[0]}, {c.max_at[1]})" if c.max_at else "-"
        lines.append(f"  {c.name:<8}{_g(c.mean_abs):>12}{_g(c.rms_abs):>12}{_g(c.max_abs):>12}  {at:<12}"
                     f"{_g(c.mean_rel):>12}{_g(c.rms_rel):>12}{_g(c.max_rel):>12}")
    lines.append(f"  Mean error = {_g(r.mean_error)}")
    lines.append(f"  RMS error = {_g(r.rms_error)}")
    lines.append(f"  Peak SNR = {_g(r.psnr)} dB")
    line = f"  Max error  = {_g(r.max_error)}"
    if r.max_at is not None and r.max_error:
        line += f" @ ({r.max_at[0]}, {r.max_at[1]}, {r.max_at[2]})"
        if r.values_at_max:
            line += ("  values are " + ", ".join(_g(v) for v in r.values_at_max[0]) + " vs "
                     + ", ".join(_g(v) for v in r.values_at_max[1]))
    lines.append(line)
    if r.flip is not None:
        lines.append(f"  FLIP ({r.flip_mode.upper()}) = {_g(r.flip)}")
    t = r.thresholds
    lines.append(f"  {r.nwarn} pixels ({100 * r.warn_share:.3g}%) over {_g(t.warn)}"
                 + (f" and {_g(t.warn_relative)} relative" if t.warn_relative else ""))
    lines.append(f"  {r.nfail} pixels ({100 * r.fail_share:.3g}%) over {_g(t.fail)}"
                 + (f" and {_g(t.fail_relative)} relative" if t.fail_relative else ""))
    lines.append(r.verdict_name)
    return "\n".join(lines)


__all__ = ["diff_text"]
