"""JSON files of the result dataclasses: arrays as nested lists, a format tag, atomic writes, clear errors on load."""

from __future__ import annotations

import json
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
    return Path(path)


def load_record(cls, path, tag, arrays, optional=()) -> dict:
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
    if not isinstance(data, dict) or data.pop("format", None) != tag:
        raise ValueError(f"{path} is not a saved synergrasp {name} (no \"format\": \"{tag}\")")
    names = [f.name for f in fields(cls)]
    missing = [key for key in names if key not in data and key not in optional]
    if missing:
        raise ValueError(f"{path} lacks the fields {missing}")
    for key, shape in arrays.items():
        data[key] = _array(data[key], shape, f"{path}: field '{key}'")
    return {k: data[k] for k in names if k in data}


def _array(value, shape, where):
    """``value`` as a float array of ``shape`` (-1: any length; None: any shape); ValueError naming ``where``."""
    try:
        arr = np.asarray(value)
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
