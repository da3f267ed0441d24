"""Camera poses: a rotation camera -> world and an eye point."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from lenslab.errors import LensError, clip


def _rx(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]], dtype=np.float64)


def _ry(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]], dtype=np.float64)


def _rz(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]], dtype=np.float64)


def rotate_rows(v: np.ndarray, r: np.ndarray) -> np.ndarray:
    """Rows of ``v`` (``(..., 3)``) turned by the 3x3 matrix ``r``: ``v @ r.T``, as a new C-ordered
    float64 array.

    Computed as one matrix product along the long axis, ``(r @ v.T).T``: NumPy's ``v @ r.T`` with a
    transposed 3x3 operand is some twenty times slower on millions of rows.
    """
    v = np.asarray(v, dtype=np.float64)
    flat = v.reshape(-1, 3)
    out = np.ascontiguousarray((np.asarray(r, dtype=np.float64) @ flat.T).T)
    return out.reshape(v.shape)


ORDERS = ("ypr", "yrp", "pyr", "pry", "ryp", "rpy")

#: the camera axis a mirror letter reflects: ``h`` x (left-right), ``v`` y (up-down), ``d`` z (front-back), as
#: ffmpeg v360's ``h_flip``, ``v_flip`` and ``d_flip``
MIRROR_AXES = {"h": 0, "v": 1, "d": 2}


def mirror_matrix(flips: str) -> np.ndarray:
    """The reflection ``diag(+-1, +-1, +-1)`` of the axes named in ``flips`` (letters of :data:`MIRROR_AXES`),
    float64 3x3."""
    m = np.ones(3)
    for c in flips:
        m[MIRROR_AXES[c]] = -1.0
    return np.diag(m)


def _mirror_letter(r: np.ndarray) -> str:
    """For an improper ``r`` (determinant -1): the one mirror letter whose reflection, applied first, leaves the
    turn with the least roll, then the least pitch (``--flip v`` of a yaw is that yaw mirrored up-down, not a yaw
    rolled half a turn and mirrored left-right); "" for a rotation."""
    if np.linalg.det(r) > 0:
        return ""

    def bent(c):
        _, pitch, roll = matrix_to_ypr(r @ mirror_matrix(c))
        return round(abs(roll), 9), round(abs(pitch), 9)
    return min("hvd", key=bent)


def ypr_matrix(yaw: float = 0.0, pitch: float = 0.0, roll: float = 0.0, order: str = "ypr") -> np.ndarray:
    """Rotation camera -> world from yaw, pitch, roll in degrees.

    Yaw turns right about +y (forward +z toward +x), pitch turns up about +x (forward toward +y),
    roll turns about +z (right +x toward up +y); by default applied roll, then pitch, then yaw:
    ``R = Ry(yaw) @ Rx(-pitch) @ Rz(roll)``. ``order`` names the product's factors left to right (the
    last is applied first), as ffmpeg v360's ``rorder`` does: ``rpy`` is ``Rz(roll) @ Rx(-pitch) @ Ry(yaw)``.

    Parameters
    ----------
    yaw, pitch, roll : float
        Angles in degrees.
    order : str
        The factors of the product, left to right: ``ypr`` (the default), ``yrp``, ``pyr``, ``pry``,
        ``ryp`` or ``rpy``.

    Returns
    -------
    numpy.ndarray
        The 3x3 rotation camera -> world, float64; its third column is the camera's forward axis in
        the world.

    Raises
    ------
    lenslab.errors.LensError
        An order that does not name y, p and r once each.

    Examples
    --------
    Yaw 90 turns forward (+z) to the right (+x); pitch 90 turns it up (+y):

    >>> from lenslab.lenses.core.pose import ypr_matrix
    >>> ypr_matrix(yaw=90)[:, 2].round(12).tolist()
    [1.0, 0.0, 0.0]
    >>> ypr_matrix(pitch=90)[:, 2].round(12).tolist()
    [0.0, 1.0, 0.0]
    """
    order = str(order).lower()
    if order not in ORDERS:
        raise LensError(f"rotation order {order!r}: give y, p and r once each, e.g. ypr or rpy")
    m = {"y": _ry(np.radians(yaw)), "p": _rx(-np.radians(pitch)), "r": _rz(np.radians(roll))}
    return m[order[0]] @ m[order[1]] @ m[order[2]]


def matrix_to_ypr(r: np.ndarray) -> tuple[float, float, float]:
    """Inverse of :func:`ypr_matrix` (degrees); pitch in [-90, 90]."""
    f = r[:, 2]  # forward in world
    yaw = np.degrees(np.arctan2(f[0], f[2]))
    pitch = np.degrees(np.arcsin(np.clip(f[1], -1.0, 1.0)))
    rest = (_rx(np.radians(pitch)) @ _ry(-np.radians(yaw))) @ r  # = Rz(roll)
    roll = np.degrees(np.arctan2(rest[1, 0], rest[0, 0]))
    return float(yaw), float(pitch), float(roll)


def look_at_matrix(eye: ArrayLike, at: ArrayLike, up: ArrayLike = (0.0, 1.0, 0.0)) -> np.ndarray:
    """Rotation camera -> world whose +z points from ``eye`` to ``at`` and whose +y leans to ``up``.

    Parameters
    ----------
    eye, at : array_like
        The camera's position and the point it looks at (world, 3 values each).
    up : array_like
        The world direction the camera's +y leans to (need not be perpendicular to the view).

    Returns
    -------
    numpy.ndarray
        The 3x3 rotation camera -> world, float64: columns right (+x), up (+y) and forward (+z).

    Raises
    ------
    lenslab.errors.LensError
        ``eye`` equal to ``at``, or ``up`` parallel to the view.

    Examples
    --------
    Looking from the origin along +x with +y up: right is -z (a right-handed frame, +x right, +y up,
    +z forward):

    >>> from lenslab.lenses.core.pose import look_at_matrix
    >>> (look_at_matrix((0, 0, 0), (5, 0, 0)).round(12) + 0.0).tolist()  # + 0.0: no -0.0
    [[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]
    """
    eye, at, up = (np.asarray(v, dtype=np.float64) for v in (eye, at, up))
    f = at - eye
    n = np.linalg.norm(f)
    if not n > 0:
        raise LensError("look-at: the eye and the target point are the same; move one of them")
    f /= n
    right = np.cross(up, f)
    rn = np.linalg.norm(right)
    if rn < 1e-12:
        raise LensError("look-at: the up vector is parallel to the viewing direction; give another up")
    right /= rn
    true_up = np.cross(f, right)
    return np.stack([right, true_up, f], axis=1)


@dataclass
class Pose:
    """Where a camera is and where it looks: a rotation camera -> world and an eye point.

    Parameters
    ----------
    rotation : array_like
        3x3 orthonormal rotation camera -> world (stored as float64); a determinant of -1 is a mirrored view
        (:attr:`mirror`: a turn after a reflection of the camera's axes, as ``lenslab warp --flip`` makes).
    eye : array_like
        The eye point in the world (3 values).

    Raises
    ------
    lenslab.errors.LensError
        A rotation that is not orthonormal (to 1e-9).

    Examples
    --------
    >>> from lenslab.lenses.core.pose import Pose
    >>> pose = Pose.from_ypr(yaw=30, pitch=-10)
    >>> [round(v, 9) + 0.0 for v in pose.ypr]
    [30.0, -10.0, 0.0]
    >>> Pose.look_at(eye=(0, 0, 0), at=(0, 0, -1)).to_dict()["yaw"]
    180.0
    """

    rotation: np.ndarray = field(default_factory=lambda: np.eye(3))
    eye: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def __post_init__(self):
        self.rotation = np.asarray(self.rotation, dtype=np.float64).reshape(3, 3)
        self.eye = np.asarray(self.eye, dtype=np.float64).reshape(3)
        if not np.allclose(self.rotation @ self.rotation.T, np.eye(3), atol=1e-9):
            raise LensError("pose: the rotation matrix is not orthonormal")

    @classmethod
    def from_ypr(cls, yaw: float = 0.0, pitch: float = 0.0, roll: float = 0.0,
                 eye: ArrayLike = (0.0, 0.0, 0.0), order: str = "ypr") -> "Pose":
        """The pose turned by :func:`ypr_matrix` (degrees), at ``eye``."""
        return cls(ypr_matrix(yaw, pitch, roll, order), np.asarray(eye, dtype=np.float64))

    @classmethod
    def look_at(cls, eye: ArrayLike, at: ArrayLike, up: ArrayLike = (0.0, 1.0, 0.0)) -> "Pose":
        """The pose at ``eye`` looking at ``at`` (:func:`look_at_matrix`)."""
        return cls(look_at_matrix(eye, at, up), np.asarray(eye, dtype=np.float64))

    @property
    def mirror(self) -> str:
        """The mirror letter of a mirrored view (``h``, ``v`` or ``d``; see :func:`mirror_matrix`): its rays are the
        turn :attr:`ypr`'s applied to the lens's rays reflected on that camera axis; "" for a rotation."""
        return _mirror_letter(self.rotation)

    @property
    def ypr(self) -> tuple[float, float, float]:
        """(yaw, pitch, roll) in degrees, pitch in [-90, 90] (:func:`matrix_to_ypr`): of the turn after the
        :attr:`mirror` of a mirrored view."""
        return matrix_to_ypr(self.rotation @ mirror_matrix(self.mirror))

    def to_dict(self) -> dict:
        """``yaw``, ``pitch``, ``roll`` (with ``mirror`` for a mirrored view) and ``eye``, or ``rotation`` when
        angles would not give it back to 1e-12, as camera files store them."""
        mirror = self.mirror
        yaw, pitch, roll = matrix_to_ypr(self.rotation @ mirror_matrix(mirror))  # (:attr:`ypr`, the mirror found once)
        out = {"yaw": yaw, "pitch": pitch, "roll": roll, **({"mirror": mirror} if mirror else {}),
               "eye": [float(v) for v in self.eye]}
        if not np.allclose(ypr_matrix(yaw, pitch, roll) @ mirror_matrix(mirror), self.rotation, atol=1e-12):
            out = {"rotation": [[float(v) for v in row] for row in self.rotation], "eye": out["eye"]}
        return out

    @classmethod
    def from_dict(cls, d: dict) -> "Pose":
        """The pose a camera file describes: ``rotation``, ``at``/``look_at`` (with ``up``), or
        ``yaw``/``pitch``/``roll``; each with an optional ``eye``, and an optional ``mirror`` (letters h, v, d:
        the camera's axes reflected before the turn)."""
        eye = d.get("eye", (0.0, 0.0, 0.0))
        mirror = d.get("mirror", "")
        if not isinstance(mirror, str) or any(c not in MIRROR_AXES for c in mirror) or len(set(mirror)) < len(mirror):
            raise LensError(f"pose: mirror must be letters among h (left-right), v (up-down) and d (front-back), "
                            f"each once, got {clip(mirror)}")
        if "rotation" in d:
            pose = cls(np.asarray(d["rotation"], dtype=np.float64), eye)
        elif "at" in d or "look_at" in d:
            pose = cls.look_at(eye, d.get("at", d.get("look_at")), d.get("up", (0.0, 1.0, 0.0)))
        else:
            pose = cls.from_ypr(d.get("yaw", 0.0), d.get("pitch", 0.0), d.get("roll", 0.0), eye)
        return cls(pose.rotation @ mirror_matrix(mirror), pose.eye) if mirror else pose
