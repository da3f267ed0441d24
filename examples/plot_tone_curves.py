"""
# Tone curves

A tone curve takes scene-linear HDR values (0 to as bright as the sun) to display values in [0, 1].
The curves differ in how they roll off the highlights and how much contrast they keep in the
mid-tones. Left: every per-pixel curve against its input, in stops from 1.0 (middle grey is the
dotted line). Right: the same HDR image, a ramp over 16 stops, through each curve.
"""

import matplotlib.pyplot as plt
import numpy as np

from lenslab.srgb import encode
from lenslab.tone import CURVES, MIDDLE_GREY, tonemap
from lenslab.tone.plot import curve_samples

per_pixel = [name for name, curve in CURVES.items() if curve.kind != "local"]
print("curves:", ", ".join(CURVES))

fig, (ax, ax_img) = plt.subplots(1, 2, figsize=(12, 5), layout="constrained", width_ratios=(1.1, 1))
for name in per_pixel:
    x, y = curve_samples(name, stops=(-8.0, 8.0))
    ax.plot(np.log2(x), encode(y), label=name, linewidth=1.4)
ax.axvline(np.log2(MIDDLE_GREY), color="0.6", linestyle=":")
ax.set_xlabel("scene-linear input, stops from 1.0")
ax.set_ylabel("display value (sRGB-encoded)")
ax.legend(fontsize=8, ncol=2)
ax.grid(alpha=0.3)

# the ramp: 2**-8 to 2**8 of an orange, each row one curve

ramp = np.exp2(np.linspace(-8, 8, 512, dtype=np.float32))[None, :, None] * np.array([1.0, 0.6, 0.25], np.float32)
rows = [encode(tonemap(np.repeat(ramp, 12, axis=0), name, exposure=0.0)) for name in per_pixel]
ax_img.imshow(np.clip(np.concatenate(rows, axis=0), 0, 1), aspect="auto", extent=(-8, 8, len(rows), 0))
ax_img.set_yticks(np.arange(len(rows)) + 0.5, per_pixel, fontsize=8)
ax_img.set_xlabel("scene-linear input, stops from 1.0")
plt.show()
