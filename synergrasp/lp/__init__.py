"""Pluggable LP backends behind one interface.

>>> import synergrasp as sg
>>> backend = sg.lp.get_backend("highs")
>>> sol = backend.solve([1.0, 1.0], [[1.0, -1.0]], [2.0])
>>> sol.status, round(sol.objective, 9), round(float(sol.y[0]), 9)
('optimal', 2.0, 1.0)

Every backend solves ``min c @ x  s.t.  A @ x == b, x >= 0`` and returns an
:class:`LPSolution` with the same dual sign convention
(``y = d objective / d b``). Backends are registered by name; an instance is
created once per name and reused (``get_backend`` returns the same object).
"""

from __future__ import annotations

import importlib

from .base import CSC, STATUSES, Backend, LPError, LPSolution

#: name -> (module, class, pip package that provides it)
_REGISTRY = {
    "highs": (".highs", "HighsBackend", "highspy"),
    "native": (".native", "NativeBackend", "numba"),
    "clarabel": (".clarabel", "ClarabelBackend", "clarabel"),
    "cvxpy": (".cvxpy", "CvxpyBackend", "cvxpy"),
}
_instances: dict[str, Backend] = {}


def _load(name):
    module, cls, _ = _REGISTRY[name]
    return getattr(importlib.import_module(module, __name__), cls)


def available_backends() -> list[str]:
    """Names of the registered backends whose solver is importable.

    Returns
    -------
    list of str
        Subset of ``["highs", "native", "clarabel", "cvxpy"]``, in that order.

    Examples
    --------
    >>> "highs" in available_backends()
    True
    """
    names = []
    for name in _REGISTRY:
        try:
            _load(name)
        except ImportError:
            continue
        names.append(name)
    return names


def get_backend(name: str | Backend = "native") -> Backend:
    """The shared backend instance for ``name`` (or ``name`` itself if a Backend).

    Parameters
    ----------
    name : str or Backend
        ``"native"`` (the default), ``"highs"``, ``"clarabel"`` or ``"cvxpy"``,
        or a ready backend object.

    Returns
    -------
    Backend

    Raises
    ------
    TypeError
        If ``name`` is neither a string nor a Backend.
    ValueError
        If the name is unknown or its solver is not installed; the message
        lists the available backends and the package to install.

    Examples
    --------
    >>> get_backend("highs").name
    'highs'
    >>> get_backend("highs") is get_backend("highs")
    True
    """
    if isinstance(name, Backend):
        return name
    if not isinstance(name, str):
        raise TypeError(f"an LP backend is a name ({available_backends()}) or a Backend object, got "
                        f"{type(name).__name__} {name!r}")
    if name not in _REGISTRY:
        raise ValueError(
            f"unknown LP backend {name!r}; available: {available_backends()} "
            f"(registered: {sorted(_REGISTRY)})"
        )
    if name not in _instances:
        try:
            cls = _load(name)
        except ImportError as exc:
            raise ValueError(
                f"LP backend {name!r} is not installed ({exc}); available: "
                f"{available_backends()}; install it with `pip install {_REGISTRY[name][2]}`"
            ) from exc
        _instances[name] = cls()
    return _instances[name]


__all__ = ["CSC", "Backend", "LPError", "LPSolution", "STATUSES", "available_backends", "get_backend"]
