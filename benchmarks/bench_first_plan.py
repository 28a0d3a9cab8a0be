"""What the first plan of a fresh install pays: compiling the numba kernels, then loading them from the cache.

Usage::

    python benchmarks/bench_first_plan.py [--object ellipsoid] [--grasp precision] [--quick] [--out DIR]

Runs, each in a new process, with numba's cache in an empty temporary folder
(``NUMBA_CACHE_DIR``, so the repository's own cache is neither used nor
touched): ``import synergrasp``, then the first plan, then a second plan; then
the same again in a second process that finds the cache the first one wrote.
The first plan of the first process pays the compilation; that of the second
process only the cache's loading. Prints wall and CPU seconds of each step and
writes them, with the number of files in the cache after each process, to
``--out``/first_plan.json (default ``./bench-out``). ``--quick`` caps the plans
at a few iterations (the compilation is the same; the test suite runs it).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from synergrasp.cli import output_folder
from synergrasp.objects import BUILTINS

ROOT = Path(__file__).resolve().parents[1]

STEPS = r'''
import json, sys, time
def clock():
    return time.perf_counter(), time.process_time()
out = {}
w, c = clock()
import synergrasp as sg
w1, c1 = clock(); out["import"] = (w1 - w, c1 - c)
obj = sg.objects.get(sys.argv[1])
w, c = clock(); sg.plan(obj, sys.argv[2], max_iter=int(sys.argv[3])); w1, c1 = clock(); out["first plan"] = (w1 - w, c1 - c)
w, c = clock(); sg.plan(obj, sys.argv[2], max_iter=int(sys.argv[3])); w1, c1 = clock(); out["second plan"] = (w1 - w, c1 - c)
print(json.dumps(out))
'''


def cache_files(cache: str) -> int:
    """Number of files numba wrote to the cache folder."""
    return sum(len(files) for _, _, files in os.walk(cache))


def run(cache: str, obj: str, grasp: str, max_iter: int) -> dict:
    env = dict(os.environ, NUMBA_CACHE_DIR=cache, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    proc = subprocess.run([sys.executable, "-c", STEPS, obj, grasp, str(max_iter)], env=env, capture_output=True,
                          text=True, cwd=tempfile.gettempdir())
    if proc.returncode:
        raise RuntimeError(proc.stderr[-2000:])
    return json.loads(proc.stdout.strip().splitlines()[-1])


def main(argv=None) -> dict:
    """Run both processes; returns ``{"max_iter", "cold", "warm", "cache_files"}`` (times: [wall s, CPU s])."""
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--object", default="ellipsoid", choices=sorted(BUILTINS),
                        help="the built-in object planned (default ellipsoid)")
    parser.add_argument("--grasp", default="precision", choices=["precision", "power"], help="grasp type (default precision)")
    parser.add_argument("--quick", action="store_true", help="plans capped at 3 iterations")
    parser.add_argument("--out", type=output_folder, default="bench-out", help="output folder (default ./bench-out)")
    args = parser.parse_args(argv)
    max_iter = 3 if args.quick else 1500
    with tempfile.TemporaryDirectory() as cache:
        cold = run(cache, args.object, args.grasp, max_iter)
        files = [cache_files(cache)]
        warm = run(cache, args.object, args.grasp, max_iter)
        files.append(cache_files(cache))
    print(f"{args.object} {args.grasp} (max_iter {max_iter}): wall s / CPU s")
    for label, result in (("empty cache (compiles)", cold), ("cache written by the first process", warm)):
        print(f"  {label}:")
        for step, (wall, cpu) in result.items():
            print(f"    {step:12s} {wall:7.2f} / {cpu:7.2f}")
    print(f"  files in the cache after the first / second process: {files[0]} / {files[1]}")
    row = {"object": args.object, "grasp": args.grasp, "max_iter": max_iter, "cold": cold, "warm": warm,
           "cache_files": files}
    (args.out / "first_plan.json").write_text(json.dumps(row, indent=1))
    return row


if __name__ == "__main__":
    main(sys.argv[1:])
