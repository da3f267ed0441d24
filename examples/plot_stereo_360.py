"""
# Stereo 360: a VR180 frame and a 3D 360 frame from one panorama

VR180 and 3D 360 video store two eyes in one frame: `stereo:sbs,base=half-equirect` puts a
180-degree equirectangular view per eye side by side, `stereo:tb,base=equirect` a whole panorama per
eye, left eye on top. `lenslab.warp` fills each eye of such a frame; from one (mono) panorama both eyes
see the same picture, because a panorama records the light arriving at one point and no reprojection
can make the parallax between two eyes. The frame is still the container a headset or a video
platform expects, and a stereo source read back gives each eye from its own half only.
"""

import matplotlib.pyplot as plt
import numpy as np

import lenslab
from lenslab.validate.sources import AnalyticSource

pano_cam = lenslab.Camera.from_spec("equirect", (1024, 512))
pano = AnalyticSource().render(pano_cam).image  # the noise-free analytic sky: sun, sky and ground

# %%
# VR180: two 180-degree half-equirect eyes side by side, each 512 x 512 of a 1024 x 512 frame. The
# centre of the left eye looks straight ahead, +z (lenslab's forward; see the conventions page).

vr180 = lenslab.Camera.from_spec("stereo:sbs,base=half-equirect", (1024, 512))
frame, alpha = lenslab.warp(pano, pano_cam, vr180, filter="bicubic")
_, ray, _ = vr180.pixel_to_world(np.array([256.0, 256.0]))
print("VR180 frame", frame.shape, "left-eye centre ray", np.round(ray, 12), "coverage", alpha.min())
assert np.allclose(ray, (0.0, 0.0, 1.0), atol=1e-12) and alpha.min() == 1.0
# one panorama, one eye point: the two eyes are the same picture, to the last bit
assert np.array_equal(frame[:, :512], frame[:, 512:])

# %%
# 3D 360 top-bottom: a whole panorama per eye, left on top; then back to a flat view. A mono output
# of a stereo source takes the left (top) eye, as ffmpeg's v360 does with `in_stereo=tb`.

tb = lenslab.Camera.from_spec("stereo:tb,base=equirect", (1024, 1024))
frame_tb, _ = lenslab.warp(pano, pano_cam, tb, filter="bicubic")
view_cam = lenslab.Camera.from_spec("perspective:fov=90", (400, 300), yaw=30, pitch=10)
view, _ = lenslab.warp(frame_tb, tb, view_cam, filter="bicubic")
direct, _ = lenslab.warp(pano, pano_cam, view_cam, filter="bicubic")
err = float(np.abs(view - direct).sum() / np.abs(direct).sum())
print(f"the top eye's view against the same view of the panorama: relative L1 {err:.2e}")
# each eye has the panorama's size, so it samples the panorama at its own pixel centres, where the
# bicubic filter gives back the stored values: the top eye is the panorama itself and the two views
# agree to float32 rounding (the wrong eye or a half-pixel shift would be off by per cent)
assert err < 1e-6

# %%


def shown(image):  # bicubic rings below 0 beside the sun: black, as a display shows it
    return np.clip(lenslab.tonemap(np.maximum(image, 0), "hable", exposure=0.5) ** (1 / 2.2), 0, 1)


fig = plt.figure(figsize=(12, 8.5), layout="constrained")
grid = fig.add_gridspec(2, 2, height_ratios=[1, 2])
ax = fig.add_subplot(grid[0, :])
ax.imshow(shown(frame))
ax.axvline(512, color="w", lw=0.8)
ax.set_title("VR180: stereo:sbs,base=half-equirect (left eye | right eye)", fontsize=9)
ax.axis("off")
ax = fig.add_subplot(grid[1, 0])
ax.imshow(shown(frame_tb))
ax.axhline(512, color="w", lw=0.8)
ax.set_title("3D 360: stereo:tb,base=equirect (left eye over right eye)", fontsize=9)
ax.axis("off")
ax = fig.add_subplot(grid[1, 1])
ax.imshow(shown(view))
ax.set_title("a 90-degree view of the 3D 360 frame (its left eye)", fontsize=9)
ax.axis("off")
plt.show()
