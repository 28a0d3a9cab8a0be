"""How the library's compiled kernels are compiled: numba, cached on disk, numpy's float semantics.

``kernel`` decorates the few loops that run on every planner iteration (the
cP broad and narrow phases, the sQ ray exits, the LP block assembly, the
contact wrenches). They are compiled at their first call and the machine
code is cached beside the module (``__pycache__``), so only the first
process after an install or an edit pays the compilation. ``error_model =
"numpy"`` makes a float division by zero give inf or NaN as in numpy, which
the callers rely on (e.g. a ray parallel to a facet plane).

Rules for kernels, for speed and for a sound cache:

* a kernel calls only kernels of its own module: numba invalidates a cached
  kernel when its source file changes, not when a kernel it calls in
  another file does;
* kernels allocate no arrays: the caller passes its outputs and scratch in
  (allocations and returned tuples cost far more compilation time than the
  loops);
* a loop over part of an array runs over a slice from 0 (``sub =
  planes[f0:f1]; for f in range(len(sub))``): ``range(f0, f1)`` compiles
  to code several times slower.

A plan's time limit is read on `clock`, which stands still while numba
compiles: the first plan after an install (about 10 s of its 27 s are
numba's compilation) gets the same search time as any later one.
"""

from __future__ import annotations

import time

import numba
from numba.core import event

#: Seconds numba has spent compiling in this process (nested compilations counted once).
_compiling = event.TimingListener()
event.register("numba:compile", _compiling)

kernel = numba.njit(cache=True, error_model="numpy")
#: For the kernels called only from other kernels: no wrapper to call them from Python (its code,
#: which unpacks every argument, is a good part of the compilation time).
helper = numba.njit(cache=True, error_model="numpy", no_cpython_wrapper=True)


def clock() -> float:
    """``time.perf_counter()`` less the seconds numba has spent compiling kernels in this process.

    Loading a kernel from the cache is not compiling; only a real compilation
    (the first call after an install or an edit of the kernel's module) stops
    this clock.

    Returns
    -------
    float
        Seconds, on the scale of ``time.perf_counter()``: only differences mean anything.
    """
    return time.perf_counter() - (_compiling.duration if _compiling.done else 0.0)
