"""Materials: Lambertian diffuse, normalised modified Phong (glossy), perfect mirror, and emission.

All surfaces are two-sided for reflection (the shading normal is turned toward the incoming ray);
emission leaves the front side only (the side the triangle's normal ``(v1-v0) x (v2-v0)`` points to)
unless the material says ``two_sided``.

BSDFs, with ``wo`` toward the viewer, ``wi`` toward the light, ``n`` the normal on ``wo``'s side:

- diffuse: ``f = kd / pi``
- glossy (normalised modified Phong, Lafortune & Willems 1994):
  ``f = kd / pi + ks (e + 2) / (2 pi) max(0, r . wi)^e`` with ``r = 2 (n . wo) n - wo``; energy
  conserving when ``kd + ks <= 1`` per channel
- mirror: ``f = ks delta(wi - r) / (n . wi)``: the reflected ray carries ``ks`` times the radiance
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from tracer.sampling import F32, INV_PI, cosine_around, dot, power_cosine, take, to_world

DIFFUSE, GLOSSY, MIRROR = 0, 1, 2
KINDS = {"diffuse": DIFFUSE, "glossy": GLOSSY, "mirror": MIRROR}


def _rgb(value, what: str) -> tuple[float, float, float]:
    arr = np.asarray(value, dtype=np.float64).ravel()
    if arr.size == 1:
        arr = np.repeat(arr, 3)
    if arr.size != 3 or not np.all(np.isfinite(arr)) or np.any(arr < 0):
        raise ValueError(f"{what} must be one or three finite non-negative numbers, got {value!r}")
    return tuple(float(v) for v in arr)


@dataclass
class Material:
    """One material. ``kind`` is ``diffuse``, ``glossy`` or ``mirror``; colours are linear RGB."""

    name: str = "default"
    kind: str = "diffuse"
    kd: tuple = (0.8, 0.8, 0.8)  # diffuse albedo
    ks: tuple = (0.0, 0.0, 0.0)  # specular (glossy lobe) or mirror reflectance
    exponent: float = 50.0  # Phong exponent of the glossy lobe
    emission: tuple = (0.0, 0.0, 0.0)  # emitted radiance
    two_sided: bool = False  # emit from both sides

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ValueError(f"material {self.name!r}: unknown kind {self.kind!r}; use one of {', '.join(KINDS)}")
        self.kd = _rgb(self.kd, f"material {self.name!r}: kd")
        self.ks = _rgb(self.ks, f"material {self.name!r}: ks")
        self.emission = _rgb(self.emission, f"material {self.name!r}: emission")
        if not (np.isfinite(self.exponent) and self.exponent >= 0):
            raise ValueError(f"material {self.name!r}: exponent must be >= 0, got {self.exponent}")
        self.exponent = float(self.exponent)
        if self.kind == "glossy" and np.any(np.add(self.kd, self.ks) > 1.0 + 1e-6):
            raise ValueError(
                f"material {self.name!r}: kd + ks exceeds 1 in some channel, which creates energy; scale them down"
            )

    @property
    def emissive(self) -> bool:
        return max(self.emission) > 0


@dataclass
class MaterialTable:
    """The materials of a scene as arrays indexed by material id (float32)."""

    materials: list = field(default_factory=list)

    def __post_init__(self):
        m = self.materials or [Material()]
        self.kind = np.array([KINDS[x.kind] for x in m], dtype=np.int8)
        self.kd = np.array([x.kd for x in m], dtype=F32)
        self.ks = np.array([x.ks for x in m], dtype=F32)
        self.exponent = np.array([x.exponent for x in m], dtype=F32)
        self.emission = np.array([x.emission for x in m], dtype=F32)
        self.two_sided = np.array([x.two_sided for x in m], dtype=bool)
        lum = lambda c: c @ np.array([0.2126, 0.7152, 0.0722], dtype=F32)  # noqa: E731
        kd_l, ks_l = lum(self.kd), lum(self.ks)
        tot = kd_l + ks_l
        # probability of sampling the diffuse lobe of a glossy material
        self.p_diffuse = np.where(tot > 0, kd_l / np.where(tot > 0, tot, 1), 1).astype(F32)
        self.has = {k: bool(np.any(self.kind == v)) for k, v in KINDS.items()}

    # -- evaluation ------------------------------------------------------------------------
    @property
    def lambertian_only(self) -> bool:
        return not (self.has["glossy"] or self.has["mirror"])

    def eval(self, mat: np.ndarray, n: np.ndarray, wo: np.ndarray, wi: np.ndarray,
             cos_i: np.ndarray | None = None, rows: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """``f(wo, wi) * max(0, n . wi)`` (N, 3) and the solid-angle pdf of sampling ``wi`` (N,).

        ``cos_i = n . wi`` may be passed when already known; with ``rows``, entry ``i`` uses
        ``n[rows[i]]`` and ``wo[rows[i]]`` (gathered only where a glossy lobe needs them). Delta
        (mirror) materials give 0 for both: they are never hit by a sampled direction.
        """
        if rows is not None and not self.lambertian_only:
            n, wo, rows = take(n, rows), take(wo, rows), None
        if cos_i is None:
            cos_i = dot(n, wi)
        pdf = np.maximum(cos_i, 0) * INV_PI
        f = take(self.kd, mat) * pdf[:, None]
        if self.lambertian_only:
            return f, pdf
        kind = self.kind[mat]
        g = np.flatnonzero(kind == GLOSSY)
        if len(g):
            mg = mat[g]
            e = self.exponent[mg]
            ng, wog = take(n, g), take(wo, g)
            r = 2 * dot(ng, wog)[:, None] * ng - wog
            lobe = (np.maximum(dot(r, take(wi, g)), 0) ** e).astype(F32)
            cg = pdf[g] * np.float32(np.pi)  # max(0, cos_i)
            f[g] += take(self.ks, mg) * (((e + 2) / (2 * np.pi)) * lobe * cg)[:, None]
            pd = self.p_diffuse[mg]
            pdf[g] = np.where(cg > 0, pd * pdf[g] + (1 - pd) * ((e + 1) / (2 * np.pi)) * lobe, 0)
        m = np.flatnonzero(kind == MIRROR)
        if len(m):
            f[m] = 0
            pdf[m] = 0
        return f, pdf

    def sample(self, mat: np.ndarray, n: np.ndarray, wo: np.ndarray, u: np.ndarray):
        """Sample ``wi``: returns ``(wi, weight = f cos / pdf, pdf, delta)``.

        ``u`` is ``(N, 3)`` uniform numbers (lobe choice, and two for the direction). ``pdf`` is the
        solid-angle density (0 for delta lobes, flagged by ``delta``). Samples below the surface get
        weight 0.
        """
        nn = len(mat)
        wi = cosine_around(n, u[:, 1], u[:, 2])
        delta = np.zeros(nn, dtype=bool)
        if self.lambertian_only:
            # cosine sampling of a Lambertian BSDF: f cos / pdf = kd exactly
            return wi, take(self.kd, mat), dot(n, wi) * INV_PI, delta
        kind = self.kind[mat]
        g = np.flatnonzero(kind == GLOSSY)
        if len(g):
            s = g[u[g, 0] >= self.p_diffuse[mat[g]]]
            if len(s):
                ns, wos = take(n, s), take(wo, s)
                r = 2 * dot(ns, wos)[:, None] * ns - wos
                wi[s] = to_world(power_cosine(u[s, 1], u[s, 2], self.exponent[mat[s]]), r)
        m = np.flatnonzero(kind == MIRROR)
        if len(m):
            nm, wom = take(n, m), take(wo, m)
            wi[m] = 2 * dot(nm, wom)[:, None] * nm - wom
            delta[m] = True
        fcos, pdf = self.eval(mat, n, wo, wi)
        ok = pdf > 0
        weight = fcos / np.where(ok, pdf, 1)[:, None]
        weight[~ok] = 0
        if len(m):
            weight[m] = take(self.ks, mat[m])  # reflect() keeps the mirror direction above the surface
        return wi, weight, pdf, delta
