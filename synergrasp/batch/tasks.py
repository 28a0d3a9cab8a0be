"""The tasks of a batch: objects named on the command line, their result keys, one task per grasp.

An OBJECTS argument is a built-in name (``ellipsoid``), a mesh or point-cloud file, or a
folder, searched recursively for files with a supported extension
(``synergrasp.objects.SUPPORTED_FORMATS``; hidden files and folders are skipped). Each object
gets a *key*, the name of its results folder: a built-in or a file is keyed by its name
(``ellipsoid``, ``mug.obj``), a file found in a folder by the folder's name and its path
inside it (``meshes/kitchen/mug.obj``). The keys do not depend on where the command runs, so
a rerun of the same command finds its results. An argument that is neither a folder nor a
file is kept as it is: loading it fails on a worker and the failure is recorded.
"""

from __future__ import annotations

import os
import warnings
from dataclasses import dataclass
from pathlib import Path

from ..hand import grasp_kind
from ..objects import BUILTINS, SUPPORTED_FORMATS


@dataclass(frozen=True)
class Task:
    """One plan of a batch.

    Attributes
    ----------
    key : str
        The object's key: its results go to ``OUT/results/KEY/GRASP.json``.
    source : str
        A built-in name or the file's absolute path.
    grasp : str
        ``"precision"`` or ``"power"``.
    """

    key: str
    source: str
    grasp: str


def expand(objects, grasps=("precision",)) -> list[Task]:
    """The tasks of a batch: every object with every grasp type, object by object.

    Parameters
    ----------
    objects : str or os.PathLike, or a sequence of them
        Built-in names, object files, or folders of object files.
    grasps : sequence of str
        Grasp types, each ``"precision"`` or ``"power"``.

    Returns
    -------
    list of Task
        In the order of ``objects`` (a folder's files sorted by path), each
        object's grasps in the order of ``grasps``; an object named twice
        counts once (a built-in in any case, ``"CUP"`` as ``"cup"``; a file
        named both directly and through its folder, under the first key).

    Raises
    ------
    ValueError
        An unknown grasp type, no objects or grasps, or two different objects
        with the same key (the message names both: pass their common folder
        instead, or rename one).
    TypeError
        If ``objects`` or ``grasps`` is not a sequence (or a single name), or an
        object is neither a string nor a path.

    Warns
    -----
    UserWarning
        For a folder that holds no object file.

    Examples
    --------
    >>> [(t.key, t.grasp) for t in expand(["ellipsoid", "cup"], ["precision", "power"])]
    [('ellipsoid', 'precision'), ('ellipsoid', 'power'), ('cup', 'precision'), ('cup', 'power')]
    """
    if isinstance(objects, (str, os.PathLike, bytes)):  # (bytes: one object, refused by name below)
        objects = [objects]
    for value, name in ((objects, "objects"), (grasps, "grasps")):
        if value is None or isinstance(value, dict) or not hasattr(value, "__iter__"):
            raise TypeError(f"{name} must be a name or a sequence of them, got {type(value).__name__}")
    grasps = [grasps] if isinstance(grasps, str) else list(grasps)
    if not grasps:
        raise ValueError("grasps is empty: give at least one grasp type ('precision' or 'power')")
    for g in grasps:
        grasp_kind(g, "each grasp type")
    sources, seen = {}, set()
    for item in objects:
        for key, source in _objects_of(item):
            if source in seen and key not in sources:  # one file named directly and through its folder: once
                continue
            seen.add(source)
            if sources.setdefault(key, source) != source:
                raise ValueError(
                    f"two objects would share the results folder '{key}': {sources[key]} and {source}; "
                    "pass their common folder instead, or rename one"
                )
    if not sources:
        raise ValueError("no objects to plan: name built-ins, object files or folders that hold some")
    return [Task(key, source, grasp) for key, source in sources.items() for grasp in dict.fromkeys(grasps)]


def _objects_of(item):
    """(key, source) pairs of one OBJECTS argument."""
    if not isinstance(item, (str, os.PathLike)):
        raise TypeError(f"an object must be a built-in name or a path, got {type(item).__name__}")
    if isinstance(item, str) and not item.strip():  # Path("") is the current folder: every file under it
        raise ValueError(f"an object name is empty ({item!r}: an unset shell variable?): give a built-in name, a file "
                         "or a folder ('.' for the current one)")
    path = Path(item)
    if path.is_dir():
        root = path.resolve()
        if not root.name:
            raise ValueError(f"cannot plan every object file under '{root}': name a folder below the root")
        found = [
            p for p in sorted(root.rglob("*"))
            if p.suffix.lower() in SUPPORTED_FORMATS and p.is_file()
            and not any(part.startswith(".") for part in p.relative_to(root).parts)
        ]
        if not found:
            warnings.warn(f"folder '{item}' holds no object file ({', '.join(SUPPORTED_FORMATS)})", UserWarning,
                          stacklevel=3)
        return [(f"{root.name}/{p.relative_to(root).as_posix()}", str(p)) for p in found]
    if str(item).lower() in BUILTINS and not path.is_file():  # a built-in in any case ("CUP"): its own name
        return [(str(item).lower(), str(item).lower())]
    key = path.name
    if key in ("", ".", ".."):
        raise ValueError(f"cannot name the results of object {str(item)!r}: give a name, a file or a folder")
    return [(key, str(path.resolve()) if path.is_file() else str(item))]
