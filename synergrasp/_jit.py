"""How the library's compiled kernels are compiled: numba, cached on disk, numpy's float semantics.

``kernel`` decorates the few loops that run on every planner iteration (the
cP broad and narrow phases, the sQ ray exits, the LP block assembly, the
contact wrenches). They are compiled at their first call and the machine
code is cached beside the module (``__pycache__``), so only the first
process after an install or an edit pays the compilation. ``error_model =
"numpy"`` makes a float division by zero give inf or NaN as in numpy, which
the callers rely on (e.g. a ray parallel to a facet plane).
"""

from __future__ import annotations

import numba

kernel = numba.njit(cache=True, error_model="numpy")
