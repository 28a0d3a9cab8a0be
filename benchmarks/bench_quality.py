"""Time per call of ``q_distance`` (value + gradients) on every LP backend, in one run.

Usage::

    python benchmarks/bench_quality.py [--repeats N]

Each backend evaluates the same sequence of grasps: contacts on a 40 mm sphere
(5 or 16 contacts, 8 cone edges), each grasp a small perturbation of the
previous one, as in a planner's iterations. Prints the median and 95th
percentile per call and the ratio of each backend's median to HiGHS's.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import synergrasp as sg


def grasp_sequence(n_contacts, length, seed=0):
    """A random walk of grasps: (points (n, 3), inward normals (n, 3)) pairs."""
    rng = np.random.default_rng(seed)
    t = 2 * np.pi * np.arange(n_contacts) / n_contacts
    base = np.c_[np.cos(t), np.sin(t), 0.3 * rng.normal(size=n_contacts)]
    grasps = []
    for _ in range(length):
        base = base + 0.01 * rng.normal(size=base.shape)
        unit = base / np.linalg.norm(base, axis=1)[:, None]
        grasps.append((40.0 * unit, -unit))
    return grasps


def time_backend(backend, grasps):
    """Seconds per call for each grasp, after one warm-up call."""
    sg.q_distance(*grasps[0], backend=backend)
    times = []
    for points, normals in grasps:
        start = time.perf_counter()
        sg.q_distance(points, normals, backend=backend)
        times.append(time.perf_counter() - start)
    return np.array(times)


def main(argv=None):
    from synergrasp.cli import positive  # (here: solvers.profile_plan imports this module beside an older package)

    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeats", type=positive(int), default=400, help="grasps per backend and size (cvxpy gets a tenth)")
    args = parser.parse_args(argv)
    print("q_distance with value + gradients, 8 cone edges; median / p95 per call in ms")
    for n in (5, 16):
        print(f"\n{n} contacts")
        medians = {}
        for backend in sg.lp.available_backends():
            count = args.repeats if backend != "cvxpy" else max(20, args.repeats // 10)
            times = time_backend(backend, grasp_sequence(n, count)) * 1e3
            medians[backend] = np.median(times)
            print(f"  {backend:9s} median {medians[backend]:8.3f}   p95 {np.percentile(times, 95):8.3f}   ({count} calls)")
        for backend, median in medians.items():
            if backend != "highs":
                print(f"  {backend} / highs = {median / medians['highs']:.1f}x")


if __name__ == "__main__":
    main()
