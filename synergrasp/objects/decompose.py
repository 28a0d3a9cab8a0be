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

#: The child's program: read the mesh, decompose it, write each part's vertices. It ends itself when its
#: standard input closes, which the system does when the parent dies (killed, not only interrupted).
_CHILD = """
import json, os, sys, threading
import numpy as np
import coacd

threading.Thread(target=lambda: (sys.stdin.read(), os._exit(1)), daemon=True).start()
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
        mesh, parts, log = (Path(folder) / name for name in ("mesh.npz", "parts.npz", "errors.txt"))
        np.savez(mesh, vertices=np.asarray(vertices, dtype=float), faces=np.asarray(faces, dtype=np.int64))
        with open(log, "wb") as errors:
            child = subprocess.Popen([sys.executable, "-c", _CHILD, str(mesh), str(parts), json.dumps(params)],
                                     stdin=subprocess.PIPE, stdout=subprocess.DEVNULL, stderr=errors)
            try:
                child.wait(timeout=time_limit)
            except subprocess.TimeoutExpired:
                raise DecompositionTimeout(f"CoACD did not finish within {time_limit:g} s") from None
            finally:
                if child.poll() is None:  # timed out, or interrupted (Ctrl-C) while waiting
                    child.kill()
                    child.wait()
                child.stdin.close()
        if child.returncode != 0:
            lines = log.read_text(errors="replace").strip().splitlines()
            status = (f"killed by signal {-child.returncode} (out of memory?)" if child.returncode < 0
                      else f"exit status {child.returncode}")
            raise RuntimeError(f"CoACD failed: {lines[-1] if lines else status}")
        with np.load(parts) as saved:
            return [saved[f"arr_{i}"] for i in range(len(saved.files))]
