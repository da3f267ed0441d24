"""The views ``lenslab demo`` warps its panorama into: each lens named in words, in a frame that fits it.

A view is a dict: ``name`` (what the card says, in words), ``spec`` (what a user would type, shown
under it), ``size``, ``pose``, ``note`` and, for the multi-view, ``tiles``. The hand-picked views come
first; then every other lens model of the registry gets a view of its own (:data:`MODEL_VIEWS` says
how each is shown: a model whose defaults would look like another lens, such as a calibrated pinhole
with no distortion, is shown with the parameters that make it itself). A model added later and not
listed there still gets a view, named by its own summary, with its defaults.
"""

from __future__ import annotations

#: models not given a view of their own: the panorama is the equirect; pincushion and barrel are the
#: two signs of the general division model
NOT_A_VIEW = {"equirect": "the panorama itself", "distortion": "shown as pincushion and barrel"}

#: model -> (name in words, spec, frame aspect (w, h), note); the spec shows what the model does
MODEL_VIEWS: dict[str, tuple[str, str, tuple[int, int], str]] = {
    "eac": ("equi-angular cube map", "eac", (3, 2), "YouTube's 360 format: six faces, angles spaced evenly"),
    "dual-fisheye": ("dual fisheye", "dual-fisheye", (2, 1),
                     "two fisheyes back to back, as a consumer 360 camera records: front lens left, back lens right"),
    "cylindrical": ("cylindrical panorama", "cylindrical:fov=360", (2, 1),
                    "straight verticals all the way round; the poles stretch away"),
    "cylindrical-equal-area": ("equal-area cylinder", "cylindrical-equal-area", (2, 1),
                               "Lambert's: every region keeps its area, shapes squash toward the poles"),
    "mercator": ("Mercator", "mercator", (1, 1), "conformal: shapes kept, sizes grow toward the poles"),
    "pannini": ("Pannini", "pannini:fov=150", (2, 1),
                "a wide view with straight verticals: 150 degrees across without perspective's stretched edges"),
    "hammer": ("Hammer-Aitoff", "hammer", (2, 1), "the whole sphere in an ellipse, equal-area"),
    "sinusoidal": ("sinusoidal", "sinusoidal", (2, 1), "the whole sphere between two sine curves, equal-area"),
    "octahedron": ("octahedral map", "octahedron", (1, 1),
                   "the whole sphere on a square: forward in the centre diamond, backward in the four corners"),
    "half-equirect": ("half equirect (VR180)", "half-equirect", (1, 1),
                      "the front hemisphere, longitude and latitude linear, 180 degrees each"),
    "little-planet": ("little planet, as a disc", "little-planet", (1, 1),
                      "the floor in the middle, the room around it: a stereographic fisheye looking straight down, "
                      "270 degrees across the disc (the little planet above fills its frame instead)"),
    "opencv": ("calibrated camera (OpenCV)", "opencv:k1=-0.3,k2=0.08", (4, 3),
               "the model of cv2.calibrateCamera, here with barrel distortion, as a calibration file gives it"),
    "kannala-brandt": ("calibrated fisheye (Kannala-Brandt)", "kannala-brandt:k1=0.05,k2=-0.02", (1, 1),
                       "OpenCV's cv2.fisheye and Kalibr's model: the image radius a polynomial of the angle from the axis"),
    "opencv-fisheye": ("full-frame calibrated fisheye (cv2.fisheye)", "opencv-fisheye:k1=-0.05", (4, 3),
                       "OpenCV's name for the Kannala-Brandt model, here on a frame inside the image circle"),
    "omnidir": ("omnidirectional camera (Mei)", "omnidir", (1, 1),
                "Mei's unified model (cv2.omnidir): a point projected on a sphere, then through a pinhole "
                "behind its centre"),
    "double-sphere": ("double sphere camera", "double-sphere:xi=-0.2,alpha=0.6", (1, 1),
                      "Basalt's and Kalibr's fisheye model, beyond 180 degrees with a closed-form inverse"),
    "eucm": ("enhanced unified camera", "eucm:alpha=0.6,beta=1.2", (1, 1),
             "Basalt's and Kalibr's EUCM: a wide lens as a projection on an ellipsoid"),
    "ocam": ("omnidirectional camera (OCamCalib)", "ocam", (1, 1),
             "Scaramuzza's model: the angle of each pixel's ray a polynomial of its radius"),
    "devernay-fov": ("FOV model (COLMAP)", "devernay-fov:omega=1.2", (1, 1),
                     "Devernay and Faugeras's distortion: one parameter, the field of view of an ideal fisheye"),
    "optics": ("chromatic aberration and vignetting", "optics:tca=1.01/0.99,vignetting=cos4,base=perspective,fov=100",
               (1, 1), "red and blue scaled 1% against green, light falling off as cos^4 toward the edges: "
               "a perspective lens with a real lens's faults (look at the edges)"),
}


def hand_views(view: int) -> list[dict]:
    """The views chosen to show the main lens families, in the order the page shows them."""
    half = max(1, view // 2)
    return [
        dict(name="perspective", spec="perspective:fov=90"),
        dict(name="fisheye, equidistant", spec="fisheye:fov=180,mapping=equidistant"),
        dict(name="fisheye, equisolid", spec="fisheye:fov=180,mapping=equisolid"),
        dict(name="fisheye, stereographic", spec="fisheye:fov=180,mapping=stereographic"),
        dict(name="fisheye, orthographic", spec="fisheye:fov=180,mapping=orthographic"),
        dict(name="tan-warped fisheye", spec="tan-fisheye:fov=180",
             note="its angle folds back past 180 degrees at 80% of the radius; beyond the fold pixels are invalid"),
        dict(name="swirl", spec="swirl:amount=6"),
        dict(name="pincushion", spec="pincushion:k1=0.3"),
        dict(name="barrel", spec="barrel:k1=-0.3"),
        dict(name="Brown distortion", spec="brown:k1=-0.05"),
        dict(name="cube map", spec="cubemap:layout=3x2", size=(3 * half, 2 * half)),
        dict(name="2x2 multi-view", spec="tiled:2x2", size=(2 * half, 2 * half), tiles=[
            {"lens": "perspective:fov=80", "yaw": 0.0},
            {"lens": "perspective:fov=80", "yaw": -50.0, "pitch": -25.0},
            {"lens": "perspective:fov=80", "yaw": 50.0, "pitch": -25.0},
            {"lens": "perspective:fov=80", "pitch": 70.0},
        ], note="four cameras sharing the panorama's eye: ahead, down-left, down-right, up at the light"),
        dict(name="little planet", spec="fisheye:dfov=300,mapping=stereographic", pose={"pitch": -90.0},
             note="a stereographic fisheye looking straight down, 300 degrees across the diagonal, so the "
                  "planet fills the frame"),
    ]


def frame(view: int, aspect: tuple[int, int]) -> tuple[int, int]:
    """A frame of ``aspect`` whose longer side is ``view`` pixels."""
    w, h = aspect
    return (view, max(1, round(view * h / w))) if w >= h else (max(1, round(view * w / h)), view)


def lens_views(view: int) -> list[dict]:
    """Every view the demo warps into: the hand-picked ones, then one per other model (see the module)."""
    from lenslab.lenses import REGISTRY

    views = hand_views(view)
    names = {v["spec"].partition(":")[0] for v in views}
    for model, cls in REGISTRY.items():
        if model in names or model in NOT_A_VIEW or not has_defaults(model):
            continue
        title, spec, aspect, note = MODEL_VIEWS.get(model, (cls.summary or model, model, (1, 1), "with its defaults"))
        views.append(dict(name=title, spec=spec, size=frame(view, aspect), note=note))
    for v in views:
        v.setdefault("size", (view, view))
        v.setdefault("pose", {})
        v.setdefault("note", "")
    return [v for v in views if v["spec"].partition(":")[0] in REGISTRY]


def has_defaults(model: str) -> bool:
    """Whether the model makes a lens from its defaults alone (a lensfun profile needs a lens name)."""
    from lenslab.errors import LensError
    from lenslab.lenses import make_lens

    try:
        make_lens(model, (64, 64))
    except LensError:
        return False
    return True
