"""Shared fixtures: every LP-dependent test runs on every available backend."""

import numpy as np
import pytest

import synergrasp as sg

BACKENDS = sg.lp.available_backends()


@pytest.fixture(params=BACKENDS)
def backend(request):
    """Name of an available LP backend (the test runs once per backend)."""
    return request.param


@pytest.fixture
def rng():
    return np.random.default_rng(12345)


def central_difference(f, x, h=1e-6):
    """Central finite-difference gradient of a scalar function of an array."""
    x = np.array(x, dtype=float)
    grad = np.zeros_like(x)
    for index in np.ndindex(x.shape):
        xp, xm = x.copy(), x.copy()
        xp[index] += h
        xm[index] -= h
        grad[index] = (f(xp) - f(xm)) / (2 * h)
    return grad


def assert_gradient(analytic, numeric, rtol=1e-5, atol=1e-8):
    """Gradient agreement relative to the gradient's own size."""
    scale = max(np.abs(numeric).max(), 1e-12)
    err = np.abs(analytic - numeric).max()
    assert err <= rtol * scale + atol, f"gradient error {err:.3g} vs scale {scale:.3g}"
