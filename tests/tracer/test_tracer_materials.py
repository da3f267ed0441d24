"""BSDFs: sampling agrees with evaluation, densities integrate correctly, energy is conserved."""

from __future__ import annotations

import numpy as np
import pytest

from tracer.materials import Material, MaterialTable
from tracer.sampling import cosine_around, uniform_sphere

N = 60_000
Z = 5.0  # standard errors allowed for Monte Carlo comparisons (chance failure ~ 6e-7 per check)


def _setup(material: Material, theta_deg: float):
    table = MaterialTable([material])
    mat = np.zeros(N, dtype=np.int32)
    n = np.tile(np.array([[0, 0, 1]], np.float32), (N, 1))
    t = np.radians(theta_deg)
    wo = np.tile(np.array([[np.sin(t), 0, np.cos(t)]], np.float32), (N, 1))
    return table, mat, n, wo


@pytest.mark.parametrize("material", [
    Material("d", kd=(0.2, 0.5, 0.8)),
    Material("g", kind="glossy", kd=(0.3, 0.2, 0.1), ks=(0.5, 0.6, 0.7), exponent=40.0),
    Material("g2", kind="glossy", kd=0.0, ks=0.9, exponent=5.0),
])
@pytest.mark.parametrize("theta", [0.0, 50.0, 80.0])
def test_sampling_and_evaluation_estimate_the_same_albedo(material, theta):
    """Directional albedo  int f cos dw  two ways: BSDF sampling weights, and uniform sphere sampling of eval."""
    table, mat, n, wo = _setup(material, theta)
    rng = np.random.default_rng(0)
    wi, weight, pdf, delta = table.sample(mat, n, wo, rng.random((N, 3), dtype=np.float32))
    assert not delta.any()
    a = weight.astype(np.float64)
    # each sample's weight is f cos / pdf as evaluated separately
    fcos, pdf_eval = table.eval(mat, n, wo, wi)
    ok = pdf_eval > 0
    np.testing.assert_allclose(pdf[ok], pdf_eval[ok], rtol=1e-5)  # same float32 formula
    np.testing.assert_allclose(weight[ok] * pdf_eval[ok, None], fcos[ok], rtol=1e-4, atol=1e-6)
    u = rng.random((N, 2), dtype=np.float32)
    wu = uniform_sphere(u[:, 0], u[:, 1])
    b = table.eval(mat, n, wo, wu)[0].astype(np.float64) * (4 * np.pi)
    ma, mb = a.mean(axis=0), b.mean(axis=0)
    se = np.sqrt(a.var(axis=0) / N + b.var(axis=0) / N)
    assert np.all(np.abs(ma - mb) <= Z * se + 1e-9), (ma, mb, se)
    assert np.all(ma <= 1.0 + Z * se), "a BSDF must not reflect more than it receives"
    # the density integrates to at most one over the sphere (glossy lobes lose what falls below)
    dens = table.eval(mat, n, wo, wu)[1].astype(np.float64) * 4 * np.pi
    assert dens.mean() <= 1 + Z * dens.std() / np.sqrt(N)


def test_lambertian_albedo_is_kd():
    table, mat, n, wo = _setup(Material("d", kd=(0.2, 0.5, 0.8)), 30.0)
    u = np.random.default_rng(1).random((N, 3), dtype=np.float32)
    wi, weight, pdf, _ = table.sample(mat, n, wo, u)
    np.testing.assert_allclose(weight, np.broadcast_to([0.2, 0.5, 0.8], weight.shape), rtol=1e-6)
    # cosine-distributed: E[cos] = 2/3 for density cos/pi, standard deviation sqrt(1/2 - 4/9)
    cos = wi[:, 2].astype(np.float64)
    assert abs(cos.mean() - 2 / 3) < Z * np.sqrt(1 / 2 - 4 / 9) / np.sqrt(N)
    assert np.all(cos >= 0)


def test_cosine_around_any_normal():
    rng = np.random.default_rng(2)
    nrm = rng.normal(size=(N, 3)).astype(np.float32)
    nrm /= np.linalg.norm(nrm, axis=1, keepdims=True)
    u = rng.random((N, 2), dtype=np.float32)
    w = cosine_around(nrm, u[:, 0], u[:, 1])
    np.testing.assert_allclose(np.linalg.norm(w, axis=1), 1, rtol=1e-5)  # float32 unit vectors
    c = np.einsum("ij,ij->i", w, nrm).astype(np.float64)
    assert c.min() > -1e-6
    assert abs(c.mean() - 2 / 3) < Z * np.sqrt(1 / 2 - 4 / 9) / np.sqrt(N)
    assert abs((c**2).mean() - 1 / 2) < Z * np.sqrt(1 / 3 - 1 / 4) / np.sqrt(N)  # E[cos^2] = 1/2, var 1/3 - 1/4


def test_mirror_reflects_exactly():
    table, mat, n, wo = _setup(Material("m", kind="mirror", kd=0.0, ks=(0.9, 0.8, 0.7)), 35.0)
    wi, weight, pdf, delta = table.sample(mat[:10], n[:10], wo[:10], np.full((10, 3), 0.5, np.float32))
    assert delta.all() and np.all(pdf == 0)
    np.testing.assert_allclose(wi, wo[:10] * [-1, -1, 1], atol=1e-7)
    np.testing.assert_allclose(weight, np.broadcast_to([0.9, 0.8, 0.7], (10, 3)))


def test_invalid_materials_are_refused():
    with pytest.raises(ValueError, match="kind"):
        Material("x", kind="velvet")
    with pytest.raises(ValueError, match="energy"):
        Material("x", kind="glossy", kd=0.6, ks=0.6)
    with pytest.raises(ValueError, match="kd"):
        Material("x", kd=(1, 2))
