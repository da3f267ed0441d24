"""
# One panorama, many lenses

A panorama holds every direction seen from one point, so any lens at that point can be made from it:
for each output pixel, the lens gives the ray, and the panorama is read where it sees that ray. Here
one noise-free HDR panorama (a sky with a sun and a checker of latitude/longitude cells, computed in
closed form) is warped into nine lenses. Pixels a lens has no ray for are transparent (alpha 0), shown
as the page's background.
"""

import matplotlib.pyplot as plt
import numpy as np

import lenslab
from lenslab.lenses import REGISTRY
from lenslab.validate.sources import AnalyticSource

# %%
# ## The panorama
#
# An equirect panorama, 1024 x 512, rendered directly from the analytic sky.

pano_cam = lenslab.Camera.from_spec("equirect", (1024, 512))
pano = AnalyticSource().render(pano_cam).image
print(f"panorama {pano.shape[1]}x{pano.shape[0]}, radiance {pano.min():.3g} to {pano.max():.3g}")

# %%
# ## Nine lenses
#
# Each view is a spec, a size and a pose. The words under each picture are the model's own summary
# (`lenslab lenses` prints them all); the spec is what you would type.

SIDE = 200
VIEWS = [
    ("perspective:fov=100", (SIDE, SIDE), {}),
    ("fisheye:fov=180,mapping=equisolid", (SIDE, SIDE), {}),
    ("fisheye:dfov=300,mapping=stereographic", (SIDE, SIDE), {"pitch": -90}),
    ("swirl:amount=6", (SIDE, SIDE), {}),
    ("pincushion:k1=0.3", (SIDE, SIDE), {}),
    ("barrel:k1=-0.3", (SIDE, SIDE), {}),
    ("pannini:fov=160", (2 * SIDE, SIDE), {}),
    ("cubemap:layout=3x2", (3 * SIDE // 2, SIDE), {}),
    ("hammer", (2 * SIDE, SIDE), {}),
]
WORDS = {"fisheye:dfov=300,mapping=stereographic": "little planet: a stereographic fisheye looking straight "
         "down, its field across the diagonal so that the planet fills the frame"}


def show(ax, image, alpha, title):
    shown = lenslab.tonemap(image / np.maximum(alpha, 1e-6)[..., None], "hable", exposure=0.5)
    rgba = np.dstack([shown ** (1 / 2.2), alpha])  # straight colour, alpha for the page's background
    ax.imshow(np.clip(rgba, 0, 1))
    ax.set_title(title, fontsize=8, wrap=True)
    ax.axis("off")


fig, axes = plt.subplots(3, 3, figsize=(11, 10), layout="constrained")
for ax, (spec, size, pose) in zip(axes.flat, VIEWS):
    cam = lenslab.Camera.from_spec(spec, size, **pose)
    image, alpha = lenslab.warp(pano, pano_cam, cam, antialias=True)
    words = WORDS.get(spec) or REGISTRY[spec.partition(":")[0]].summary
    show(ax, image, alpha, f"{words}\n{spec}")
    print(f"{spec:42s} {size[0]}x{size[1]}  covers {alpha.mean():6.1%} of its frame")
fig.patch.set_alpha(0)
plt.show()
