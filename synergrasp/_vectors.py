"""Small vector helpers shared by the geometry code."""

from __future__ import annotations

import numpy as np


def sphere_directions(n):
    """(n, 3) unit vectors spread evenly over the sphere (a Fibonacci lattice).

    Parameters
    ----------
    n : int

    Returns
    -------
    (n, 3) float

    Examples
    --------
    >>> d = sphere_directions(64)
    >>> d.shape, bool(np.allclose(np.linalg.norm(d, axis=1), 1.0)), bool(np.abs(d.mean(axis=0)).max() < 0.02)
    ((64, 3), True, True)
    """
    z = np.linspace(1.0 - 1.0 / n, -1.0 + 1.0 / n, n)
    angle = np.arange(n) * np.pi * (3.0 - np.sqrt(5.0))
    return np.stack([np.sqrt(1.0 - z**2) * np.cos(angle), np.sqrt(1.0 - z**2) * np.sin(angle), z], axis=1)


#: The Levi-Civita symbol: ``(a x b)_i = eps_ijk a_j b_k``.
_LEVI_CIVITA = np.zeros((3, 3, 3))
_LEVI_CIVITA[[0, 1, 2], [1, 2, 0], [2, 0, 1]] = 1.0
_LEVI_CIVITA[[0, 1, 2], [2, 0, 1], [1, 2, 0]] = -1.0
_LEVI_CIVITA.setflags(write=False)
#: Up to this many input entries in all, `cross` uses one einsum call; above, the written-out components.
_SMALL = 96


def cross(a, b):
    """Cross product over the last axis of broadcast ``(..., 3)`` arrays.

    Much faster than ``numpy.cross`` on the small arrays of the planner and
    with the same result (each component is ``a_j b_k - a_k b_j``, rounded
    once): small inputs go through one ``einsum`` with the Levi-Civita symbol
    (the least call overhead), larger ones through the three components
    written out (einsum's three-operand loop does 27 products per result).

    Parameters
    ----------
    a, b : (..., 3) float ndarray

    Returns
    -------
    (..., 3) float ndarray

    Examples
    --------
    >>> cross(np.array([1.0, 0.0, 0.0]), np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])).tolist()
    [[0.0, 0.0, 1.0], [0.0, -1.0, 0.0]]
    """
    if a.size + b.size <= _SMALL:
        return np.einsum("ijk,...j,...k->...i", _LEVI_CIVITA, a, b)
    a, b = np.broadcast_arrays(a, b)
    out = np.empty(a.shape)
    for i, j, k in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
        np.subtract(a[..., j] * b[..., k], a[..., k] * b[..., j], out=out[..., i])
    return out


def unit_rows(v):
    """Rows of ``v`` (..., 3) scaled to unit length; zero rows stay zero."""
    norm = np.sqrt(np.add.reduce(v * v, axis=-1, keepdims=True))  # numpy.linalg.norm's sum, without its dispatch
    return np.divide(v, norm, out=np.zeros_like(v), where=norm > 0)
