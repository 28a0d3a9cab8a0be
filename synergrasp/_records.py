"""JSON files of the result dataclasses: arrays as nested lists, a format tag, atomic writes, clear errors on load."""

from __future__ import annotations

import json
import math
from dataclasses import asdict, fields
from pathlib import Path

import numpy as np

from ._checks import as_path
from ._files import atomic_path


def save_record(record, path, tag, arrays) -> Path:
    """Write a dataclass as JSON (floats round-trip exactly).

    Parameters
    ----------
    record : dataclass instance
    path : str or Path
    tag : str
        Format tag stored as ``"format"`` (e.g. ``"synergrasp.PlanResult/1"``).
    arrays : dict of str to tuple or None
        The array fields and the shapes they are read back with (``-1`` for
        any length, None: as stored).

    Returns
    -------
    Path

    Raises
    ------
    TypeError
        If ``path`` is not a path.
    FileNotFoundError
        If its folder does not exist.

    Notes
    -----
    The file is written atomically (`synergrasp._files.atomic_path`): an
    interrupted or failed write leaves no partial file.
    """
    data = asdict(record)
    for name in arrays:
        data[name] = np.asarray(data[name]).tolist()
    data["format"] = tag
    text = json.dumps(data, indent=1)
    with atomic_path(path) as tmp:
        tmp.write_text(text)
    return as_path(path, "the record's path")


def load_record(cls, path, tag, arrays, optional=(), missing="") -> dict:
    """The fields of a dataclass saved by `save_record`.

    Parameters
    ----------
    cls : dataclass type
    path : str or Path
    tag : str
    arrays : dict of str to tuple
        The array fields and their shapes, as given to `save_record`.
    optional : tuple of str
        Fields a file may lack (written before they existed); they are left
        out of the result, for their defaults.
    missing : str
        What to do about a file that lacks other fields (said in the error).

    Returns
    -------
    dict
        Keyword arguments of ``cls`` (arrays as float ndarrays).

    Raises
    ------
    FileNotFoundError
        If there is no such file (or it is a folder).
    ValueError
        If the file cannot be read, is not JSON, has another format tag, lacks
        fields, or an array field is not numbers of its shape; the message names
        the file (and the field).
    """
    path = as_path(path, f"the {cls.__name__} file")
    name = cls.__name__
    if path.is_dir():
        raise FileNotFoundError(f"'{path}' is a folder, not a {name} file: give the .json file a {name} was saved to")
    if not path.is_file():
        raise FileNotFoundError(f"{name} file not found: '{path}'")
    try:
        data = json.loads(path.read_text())
    except (OSError, UnicodeDecodeError, json.JSONDecodeError, RecursionError) as exc:  # (lists nested 1e5 deep)
        raise ValueError(f"cannot read a {name} from {path}: {exc}") from exc
    found = data.pop("format", None) if isinstance(data, dict) else None
    if found != tag:
        family = tag.rsplit("/", 1)[0] + "/"
        if isinstance(found, str) and found.startswith(family):
            raise ValueError(f"{path} is a {name} of format {found!r}, which this version of synergrasp does not read "
                             f"(it reads {tag!r}): read it with the version that wrote it")
        raise ValueError(f"{path} is not a saved synergrasp {name} (no \"format\": \"{tag}\")")
    names = [f.name for f in fields(cls)]
    lacking = [key for key in names if key not in data and key not in optional]
    if lacking:
        raise ValueError(f"{path} lacks the fields {lacking}" + (f": {missing}" if missing else ""))
    for key, shape in arrays.items():
        data[key] = _array(data[key], shape, f"{path}: field '{key}'")
    return {k: data[k] for k in names if k in data}


def _array(value, shape, where):
    """``value`` as a float array of ``shape`` (-1: any length; None: any shape); ValueError naming ``where``."""
    try:
        arr = None if holds_bool(value) else np.asarray(value)  # (numpy reads true as 1.0 beside numbers)
    except (TypeError, ValueError):  # ragged lists
        arr = None
    if arr is not None:  # numbers only: JSON's strings, true/false and null are not read as numbers
        arr = arr.astype(float) if arr.size == 0 or arr.dtype.kind in "iuf" else None
    if arr is not None and shape is not None:
        if arr.size == 0:  # an empty list reads back as shape (0,)
            arr = arr.reshape([0 if n == -1 else n for n in shape])
        elif arr.ndim != len(shape) or any(n not in (-1, m) for n, m in zip(shape, arr.shape)):
            arr = None
    if arr is None:
        text = repr(value)
        dims = "" if shape is None else " of shape (" + ", ".join("n" if n == -1 else str(n) for n in shape) + ("," if len(shape) == 1 else "") + ")"
        raise ValueError(f"{where} must be an array of numbers{dims}, got {text[:60] + '...' if len(text) > 60 else text}")
    return arr


class FieldChecks:
    """Checks of the fields of a loaded record (`load_record`'s dict); each error names the file and the field.

    Parameters
    ----------
    data : dict
    path : str or Path
    """

    def __init__(self, data: dict, path):
        self.data, self.path = data, path

    def fail(self, name: str, what: str):
        """Raise the ValueError: field ``name`` must be ``what``."""
        value = repr(self.data[name])
        raise ValueError(f"{self.path}: field '{name}' must be {what}, got {value[:60] + '...' if len(value) > 60 else value}")

    def array(self, name: str, ndim: int, finite: bool = True) -> np.ndarray:
        """Field ``name`` as a float array of ``ndim`` dimensions (an empty 2-D one as (0, 3)), finite if asked."""
        try:
            arr = np.asarray(self.data[name], dtype=float)
        except (TypeError, ValueError):
            self.fail(name, f"a {ndim}-D array of numbers")
        if arr.ndim != ndim:
            if arr.size == 0 and ndim == 2:  # an empty list: no rows
                return arr.reshape(0, 3)
            self.fail(name, f"a {ndim}-D array of numbers (shape {arr.shape})")
        if finite and not np.isfinite(arr).all():
            self.fail(name, "finite numbers")
        return arr

    def integer(self, name: str, low: int = 0) -> int:
        """Field ``name``: an integer >= ``low`` (not a bool)."""
        value = self.data[name]
        if isinstance(value, bool) or not isinstance(value, int) or value < low:
            self.fail(name, f"an integer >= {low}")
        return value

    def number(self, name: str, low: float | None = None, nan: bool = False) -> float:
        """Field ``name``: a finite number >= ``low`` (NaN too with ``nan``)."""
        value = self.data[name]
        try:  # (an int beyond a float's range overflows)
            ok = not isinstance(value, bool) and isinstance(value, (int, float)) and (
                math.isfinite(float(value)) or (nan and math.isnan(value)))
        except OverflowError:
            ok = False
        if not ok or (low is not None and value < low):
            self.fail(name, "a finite number" + (f" >= {low}" if low is not None else "") + (" or NaN" if nan else ""))
        return float(value)

    def text(self, name: str) -> str:
        """Field ``name``: a string."""
        if not isinstance(self.data[name], str):
            self.fail(name, "a string")
        return self.data[name]

    def strings(self, name: str, what: str) -> list:
        """Field ``name``: a list of strings (``what`` says what they are, in the error)."""
        value = self.data[name]
        if not isinstance(value, list) or not all(isinstance(item, str) for item in value):
            self.fail(name, f"a list of {what}")
        return value

    def flag(self, name: str) -> bool:
        """Field ``name``: true or false."""
        if not isinstance(self.data[name], bool):
            self.fail(name, "true or false")
        return self.data[name]


def holds_bool(value) -> bool:
    """Whether nested lists ``value`` hold a true or false anywhere (numpy reads them as 1.0 and 0.0 beside numbers)."""
    stack = [value]
    while stack:
        item = stack.pop()
        if isinstance(item, bool):
            return True
        if isinstance(item, list):
            stack.extend(item)
    return False
