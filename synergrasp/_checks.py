"""Input validation shared by the public functions: clear errors, named arguments."""

from __future__ import annotations

import math
import numbers
import os

from pathlib import Path

import numpy as np


def as_points(value, name: str, dim: int | None = None, min_dim: int = 1) -> np.ndarray:
    """Validate a point set and return it as a float array.

    Parameters
    ----------
    value : (n, d) array_like
        The points.
    name : str
        Argument name used in error messages.
    dim : int, optional
        Required dimension ``d``.
    min_dim : int
        Smallest allowed ``d`` when ``dim`` is not given.

    Returns
    -------
    (n, d) float ndarray

    Raises
    ------
    TypeError
        If the value is not numeric.
    ValueError
        If it is not 2-D, is empty, has the wrong dimension or a non-finite entry (an integer beyond a
        float's range included).
    """
    arr = _numbers(value, name, "a numeric array of shape (n, d)")
    if arr.ndim != 2:
        raise ValueError(f"{name} must have shape (n, d), got shape {arr.shape}")
    if arr.shape[0] == 0:
        raise ValueError(f"{name} is empty: it needs at least one point")
    if dim is not None and arr.shape[1] != dim:
        flipped = ""
        if arr.shape[0] == dim < arr.shape[1]:  # a (3, n) array of n points
            flipped = f" (an array of shape ({dim}, n)? pass its transpose, one point per row)"
        raise ValueError(f"{name} has points of dimension {arr.shape[1]}, expected {dim}{flipped}")
    if arr.shape[1] < min_dim:
        raise ValueError(f"{name} has dimension {arr.shape[1]}, at least {min_dim} is required")
    if not np.isfinite(arr).all():
        rows = np.flatnonzero(~np.isfinite(arr).all(axis=1))
        listed = ", ".join(map(str, rows[:10])) + (", ..." if len(rows) > 10 else "")
        raise ValueError(f"{name} contains NaN or inf at rows [{listed}]"
                         + ("" if len(rows) <= 10 else f" ({len(rows)} of {len(arr)}; keep the finite ones with "
                                                        "points[np.isfinite(points).all(axis=1)])"))
    return arr


class EntryTypeError(TypeError):
    """An entry of an array of Python objects that is not a real number (its type's name is the message)."""


def numeric(value) -> np.ndarray:
    """``value`` as floats; real numbers only: not text, booleans, complex numbers, dates or masked entries."""
    if type(value) is np.ndarray and value.dtype == np.float64:  # already floats (the common case)
        return value
    if np.ma.isMaskedArray(value) and np.ma.getmaskarray(value).any():
        raise TypeError("masked entries")
    raw = np.asarray(value)
    if raw.dtype.kind == "O":  # Python objects: each must be a real number itself ("1" and True convert to floats)
        for v in raw.flat:
            if isinstance(v, (bool, np.bool_)) or not isinstance(v, (numbers.Real, np.integer, np.floating)):
                raise EntryTypeError(type(v).__name__)
    elif raw.dtype.kind not in "iuf":
        raise TypeError(raw.dtype.name)
    return np.asarray(raw, dtype=float)


def _numbers(value, name: str, what: str) -> np.ndarray:
    """`numeric` of ``value``, its errors naming ``name`` (``what`` it must be): an entry beyond a float's range as
    not finite (ValueError), anything not a real number as a TypeError."""
    try:
        return numeric(value)
    except OverflowError:
        raise ValueError(f"{name} has an entry beyond a float's range (about 1.8e308): not finite") from None
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name} must be {what}, got {_kind(value, exc)}") from exc


def as_vector(value, name: str, size: int | None = None) -> np.ndarray:
    """Validate a finite 1-D vector (optionally of a given size)."""
    arr = _numbers(value, name, "a numeric vector")
    if arr.ndim != 1 or (size is not None and arr.shape[0] != size):
        expected = f"({size},)" if size is not None else "(n,)"
        raise ValueError(f"{name} must have shape {expected}, got shape {arr.shape}")
    if not np.isfinite(arr).all():
        raise ValueError(f"{name} contains NaN or inf")
    return arr


def as_path(value, what: str) -> Path:
    """A file path given as a str or os.PathLike (not a dict, None, an empty name), ``~`` expanded; ``what`` names it."""
    if not isinstance(value, (str, os.PathLike)):
        raise TypeError(f"{what} must be a str or os.PathLike, got {type(value).__name__}")
    if isinstance(value, str) and not value.strip():  # Path("") is the current folder
        raise ValueError(f"{what} is an empty name (an unset variable?): give a path")
    return Path(value).expanduser()


def _real(value, name: str) -> float:
    """``value`` as a float (an int beyond a float's range as inf); TypeError naming ``name`` if it is not a real number."""
    try:
        if isinstance(value, (str, bytes, bool, np.bool_, complex, np.complexfloating)):
            raise TypeError(type(value).__name__)
        return float(value)
    except OverflowError:
        return math.inf
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name} must be a number, got {type(value).__name__}") from exc


def finite_scalar(value, name: str, what: str = "a finite number") -> float:
    """Validate a finite real number (``what`` says what it is, in the error)."""
    out = _real(value, name)
    if not math.isfinite(out):
        raise ValueError(f"{name} must be {what}, got {value!r}")
    return out


def positive_scalar(value, name: str, maximum: float | None = None, *, zero: bool = False) -> float:
    """Validate a finite, strictly positive number (0 too with ``zero``; at most ``maximum`` if given)."""
    out = _real(value, name)
    if not math.isfinite(out) or out < 0 or (out == 0 and not zero):
        raise ValueError(f"{name} must be a finite number {'>=' if zero else '>'} 0, got {value!r}")
    if maximum is not None and out > maximum:
        raise ValueError(f"{name} must be a number in {'[' if zero else '('}0, {maximum:g}], got {value!r}")
    return out


def integer(value, name: str, minimum: int = 1, what: str = "") -> int:
    """Validate a whole number >= ``minimum`` (bools refused); ``what`` says what it counts."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}{f' ({what})' if what else ''}, got {value!r}")
    return int(value)


def _kind(value, error=None) -> str:
    """How a value that is not a numeric array is named in messages (with the entry `numeric` refused, ``error``)."""
    if isinstance(error, EntryTypeError) and isinstance(value, (list, tuple, np.ndarray)) and np.ndim(value):
        return f"{_kind(value)} with an entry of type {error} (real numbers only)"
    if np.ma.isMaskedArray(value):
        return "a masked array with masked entries (fill or drop them first)"
    if isinstance(value, np.ndarray):
        return f"an array of dtype {value.dtype}"
    try:
        kind = np.asarray(value).dtype.kind
    except (TypeError, ValueError):
        kind = ""
    if kind in ("U", "S"):
        return f"a {type(value).__name__} of text"
    if kind == "b":
        return f"a {type(value).__name__} of booleans"
    try:
        complex_values = np.iscomplexobj(value) and not isinstance(value, (str, bytes))
    except (TypeError, ValueError):  # ragged nested lists
        return f"a ragged {type(value).__name__}"
    return "complex numbers" if complex_values else type(value).__name__
