"""
# Undistorting a calibrated fisheye

A camera calibrated with OpenCV's `cv2.fisheye` (the Kannala-Brandt model; Kalibr and COLMAP write
the same) is a lenslab lens: `kannala-brandt:fx=...,k1=...` or the calibration file itself. Here a
"photo" through such a fisheye is rendered from the noise-free analytic sky, then undistorted into a
100-degree perspective view with `lenslab.warp`. The same map from OpenCV's own
`cv2.fisheye.initUndistortRectifyMap` is the outside check: the two must agree to a small fraction
of a pixel wherever both are defined.
"""

import cv2
import matplotlib.pyplot as plt
import numpy as np

import lenslab
from lenslab.validate.sources import AnalyticSource

W, H = 640, 480
K = np.array([[230.0, 0.0, 319.5], [0.0, 230.0, 239.5], [0.0, 0.0, 1.0]])  # OpenCV pixels: centres at integers
D = np.array([0.05, -0.01, 0.002, 0.0])
spec = "kannala-brandt:fx=230,fy=230,cx=319.5,cy=239.5,k1=0.05,k2=-0.01,k3=0.002,k4=0"
fisheye = lenslab.Camera.from_spec(spec, (W, H), pitch=25)
photo = AnalyticSource().render(fisheye, spp=4).image  # the distorted "photo"

# %%
# Undistort: a perspective camera with the same pose. Its focal length in pixels follows from its
# field of view: `fx = (W / 2) / tan(fov / 2)`.

fov = 100.0
flat = lenslab.Camera.from_spec(f"perspective:fov={fov}", (W, H), pitch=25)
undistorted, alpha = lenslab.warp(photo, fisheye, flat, samples=4)

# OpenCV's map for the same output camera (its principal point at the image centre, in its pixels)
f = (W / 2) / np.tan(np.radians(fov / 2))
K_new = np.array([[f, 0.0, W / 2 - 0.5], [0.0, f, H / 2 - 0.5], [0.0, 0.0, 1.0]])
map_x, map_y = cv2.fisheye.initUndistortRectifyMap(K, D, np.eye(3), K_new, (W, H), cv2.CV_32FC1)

# lenslab's map: where each output pixel centre's ray lands in the fisheye image (lenslab pixels are
# OpenCV's + 0.5: the corner, not the centre, of the first pixel is 0)
y, x = np.mgrid[0:H, 0:W] + 0.5
_, rays, _ = flat.pixel_to_world(np.stack([x, y], axis=-1))
src_xy, seen = fisheye.world_to_pixel(rays)
diff = np.hypot(src_xy[..., 0] - (map_x + 0.5), src_xy[..., 1] - (map_y + 0.5))[seen]
print(f"lenslab vs cv2.fisheye.initUndistortRectifyMap over {seen.mean():.1%} of the output: "
      f"largest difference {diff.max():.1e} px, mean {diff.mean():.1e} px (OpenCV's map is float32)")
# float32 holds a 640-pixel position to 3e-5 px; the build of this page fails if the two maps part
assert seen.mean() > 0.99 and diff.max() < 1e-3

# %%

fig, axes = plt.subplots(1, 2, figsize=(12, 4.6), layout="constrained")
for ax, image, title in ((axes[0], photo, f"the fisheye photo ({spec.split(':')[0]}, OpenCV's cv2.fisheye)"),
                         (axes[1], undistorted, f"undistorted by lenslab.warp: perspective, {fov:g} degrees")):
    ax.imshow(np.clip(lenslab.tonemap(image, "hable", exposure=0.5) ** (1 / 2.2), 0, 1))
    ax.set_title(title, fontsize=9)
    ax.axis("off")
plt.show()
