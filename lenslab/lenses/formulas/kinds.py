"""The projection codes, enumerated once: the compiled kernels dispatch on them and the models pass them.

A projection takes a unit direction to a point ``(x, y)`` of the image plane at unit focal length
(and back). The azimuthal ones (fisheyes) depend only on the angle ``theta`` from the axis:
``s = sqrt(x^2 + y^2)`` is a function of ``theta`` (:mod:`lenslab.lenses.formulas.azimuthal`).
"""

from __future__ import annotations

#: central projection ``(x, y) = (dx, dy) / dz`` (pinhole, rectilinear)
RECTILINEAR = 0
#: ``x = longitude``, ``y = latitude``
EQUIRECTANGULAR = 1
#: central cylinder: ``x = longitude``, ``y = dy / hypot(dx, dz)`` (lensfun's "panoramic")
CYLINDRICAL = 2
#: azimuthal: ``s = theta``
EQUIDISTANT = 3
#: azimuthal, equal areas: ``s = 2 sin(theta / 2)``
EQUISOLID = 4
#: azimuthal, conformal: ``s = 2 tan(theta / 2)``
STEREOGRAPHIC = 5
#: azimuthal: ``s = sin(theta)``, front hemisphere only
ORTHOGRAPHIC = 6
#: azimuthal, lensfun's fit of Thoby: ``s = K1 sin(K2 theta)``
THOBY = 7
#: Mei's unified model: ``(x, y) = (dx, dy) / (dz + xi)``
UNIFIED = 8
#: Usenko et al.'s double sphere
DOUBLE_SPHERE = 9
#: the enhanced unified camera model
EUCM = 10
#: Devernay and Faugeras's FOV model: rectilinear, then ``r_d = atan(2 r_u tan(omega/2)) / omega``
FOV = 11

#: Lambert's cylindrical equal-area: ``x = longitude``, ``y = sin(latitude)``
EQUAL_AREA_CYLINDRICAL = 12
#: Mercator: ``x = longitude``, ``y = atanh(sin(latitude))``
MERCATOR = 13

#: the azimuthal codes by their usual names (fisheye mappings; lensfun calls equidistant "fisheye")
AZIMUTHAL = {"equidistant": EQUIDISTANT, "equisolid": EQUISOLID, "stereographic": STEREOGRAPHIC,
             "orthographic": ORTHOGRAPHIC, "thoby": THOBY}

#: lensfun's projection types (``<type>`` in its database) by code
LENSFUN = {"rectilinear": RECTILINEAR, "equirectangular": EQUIRECTANGULAR, "panoramic": CYLINDRICAL,
           "fisheye": EQUIDISTANT, "equisolid": EQUISOLID, "stereographic": STEREOGRAPHIC,
           "orthographic": ORTHOGRAPHIC, "thoby": THOBY}

#: lensfun's Thoby fisheye: ``s = 1.47 sin(0.713 theta)``
THOBY_K1, THOBY_K2 = 1.47, 0.713
