"""JSON files of the result dataclasses: arrays as nested lists, a format tag, clear errors on load."""

from __future__ import annotations

import json
from dataclasses import asdict, fields
from pathlib import Path

import numpy as np


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
    """
    data = asdict(record)
    for name in arrays:
        data[name] = np.asarray(data[name]).tolist()
    data["format"] = tag
    path = Path(path)
    path.write_text(json.dumps(data, indent=1))
    return path


def load_record(cls, path, tag, arrays) -> dict:
    """The fields of a dataclass saved by `save_record`.

    Parameters
    ----------
    cls : dataclass type
    path : str or Path
    tag : str
    arrays : dict of str to tuple
        The array fields and their shapes, as given to `save_record`.

    Returns
    -------
    dict
        Keyword arguments of ``cls`` (arrays as float ndarrays).

    Raises
    ------
    ValueError
        If the file cannot be read, is not JSON, has another format tag or lacks fields.
    """
    path = Path(path)
    name = cls.__name__
    try:
        data = json.loads(path.read_text())
    except (OSError, json.JSONDecodeError) as exc:
        raise ValueError(f"cannot read a {name} from {path}: {exc}") from exc
    if not isinstance(data, dict) or data.pop("format", None) != tag:
        raise ValueError(f"{path} is not a saved synergrasp {name}")
    names = {f.name for f in fields(cls)}
    missing = names - set(data)
    if missing:
        raise ValueError(f"{path} lacks the fields {sorted(missing)}")
    for key, shape in arrays.items():
        data[key] = np.asarray(data[key], dtype=float)
        if shape is not None:  # an empty list reads back as shape (0,)
            data[key] = data[key].reshape(shape)
    return {k: data[k] for k in names}
