"""CoACD's convex decomposition, run in a child process with a time limit.

CoACD can loop without end on some shapes (two bodies or the sides of a slot
about one remeshing voxel apart), inside C++ code that no signal interrupts.
`run_coacd` therefore runs it in a separate Python process, which imports only
numpy and coacd, and kills it when ``time_limit`` seconds have passed. For a
given input the parts are those of ``coacd.run_coacd`` in this process.
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

#: The child's program: read the mesh, decompose it, write each part's vertices.
_CHILD = """
import json, sys
import numpy as np
import coacd

mesh = np.load(sys.argv[1])
coacd.set_log_level("error")
parts = coacd.run_coacd(coacd.Mesh(mesh["vertices"], mesh["faces"]), **json.loads(sys.argv[3]))
np.savez(sys.argv[2], *[np.asarray(vertices, dtype=float) for vertices, _ in parts])
"""


class DecompositionTimeout(RuntimeError):
    """CoACD did not finish within its time limit (the child process was killed)."""


def run_coacd(vertices, faces, params: dict, time_limit: float) -> list[np.ndarray]:
    """The vertices of CoACD's convex parts of a triangle mesh.

    Parameters
    ----------
    vertices : (n, 3) float
    faces : (m, 3) int
    params : dict
        Keyword arguments of ``coacd.run_coacd`` (JSON values).
    time_limit : float
        Seconds the decomposition may take.

    Returns
    -------
    list of (k_i, 3) float
        One array per part, in CoACD's order.

    Raises
    ------
    DecompositionTimeout
        If it takes longer than ``time_limit``.
    RuntimeError
        If the child process fails (its last line of error output is quoted).
    """
    with tempfile.TemporaryDirectory(prefix="synergrasp-coacd-") as folder:
        mesh, parts = Path(folder) / "mesh.npz", Path(folder) / "parts.npz"
        np.savez(mesh, vertices=np.asarray(vertices, dtype=float), faces=np.asarray(faces, dtype=np.int64))
        child = subprocess.Popen([sys.executable, "-c", _CHILD, str(mesh), str(parts), json.dumps(params)],
                                 stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        try:
            _, errors = child.communicate(timeout=time_limit)
        except subprocess.TimeoutExpired:
            raise DecompositionTimeout(f"CoACD did not finish within {time_limit:g} s") from None
        finally:
            if child.poll() is None:  # timed out, or interrupted (Ctrl-C) while waiting
                child.kill()
                child.communicate()
        if child.returncode != 0:
            last = (errors or "").strip().splitlines()[-1:] or [f"exit status {child.returncode}"]
            raise RuntimeError(f"CoACD failed: {last[0]}")
        with np.load(parts) as saved:
            return [saved[f"arr_{i}"] for i in range(len(saved.files))]
