"""Batch planning on Dask: throughput with 2 workers against 1, overhead against a loop, interrupt and rerun.

Usage::

    python benchmarks/bench_batch.py [--quick] [--out DIR]

The tasks: the 22 meshes of ``benchmarks/meshes`` and the built-in ellipsoid, cup and goblet,
each with a precision and a power grasp (50 plans); ``--quick``: the three built-ins only
(6 plans, for the tests). In one run:

1. **loop**: the tasks one after the other in this process, through the function a worker
   runs (``plan_task``, which loads each object once) and the writer of a batch (``ResultStore``);
2. **dask, 1 worker** and 3. **dask, 2 workers**: ``synergrasp.batch.run`` on a local cluster
   of that size, started and warmed up (one short plan per worker) before the clock starts;
   the time is the batch's own, from the first task submitted to the last result written;
4. **outcomes**: every task's result file the same in the three runs, bit for bit but for
   the timings (the plan's ``time_s`` and the reach's ``cpu_time``);
5. **interrupt**: ``synergrasp batch`` on 2 workers, killed with its workers (SIGKILL) once a
   third of the results are written, then run again to the end, and compared with run 3:
   the same result files with the same content, no temporary file, one summary row per task;
6. **memory setting**: the loop again in two fresh processes, with and without the
   ``MALLOC_TRIM_THRESHOLD_=65536`` that Dask's nannies set by default (and that
   ``synergrasp.batch.local_cluster`` drops): CPU time and minor page faults.

Prints the wall times, the ratio of the 1-worker to the 2-worker time (target >= 1.6 on a
2-core machine), the overhead per task of Dask against the loop (target <= 10 %) in wall time
and in CPU time (the workers' and the client's against the loop's; less sensitive to other
jobs on the machine), the verdicts, and the load average before and after (the wall-clock
timings need an idle machine).
Writes under ``DIR`` (default ``bench-out/batch``): ``loop``, ``dask-1``, ``dask-2``,
``interrupted``, ``malloc``.
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import resource
import shutil
import signal
import subprocess
import sys
import time
import warnings
from pathlib import Path

import synergrasp as sg
from synergrasp.batch import ResultStore, expand, load_object, local_cluster, plan_task
from synergrasp.cli import output_folder

ROOT = Path(__file__).resolve().parents[1]
MESHES = ROOT / "benchmarks" / "meshes"
BUILTINS = ["ellipsoid", "cup", "goblet"]
GRASPS = ["precision", "power"]


def warm_up():
    """One short plan, so that a process has imported and initialised what planning needs."""
    plan_task("ellipsoid", "precision", options={"max_iter": 5})


def loop(tasks, out):
    """The tasks in this process, one by one.

    Returns the wall time (s) and the CPU time (s) of what a batch's client does per result:
    writing it, and reading all of them back for the summary table.
    """
    store = ResultStore(out)
    store.check_writable()
    start, writing = time.perf_counter(), 0.0
    for task in tasks:
        outcome, _, _ = plan_task(task.source, task.grasp)  # loads each object once, as a worker does
        cpu = time.process_time()
        store.write_result(task.key, task.grasp, outcome)
        writing += time.process_time() - cpu
    wall = time.perf_counter() - start
    cpu = time.process_time()
    store.write_summary(store.scan()[0])
    return wall, writing + time.process_time() - cpu


def on_dask(objects, workers, out):
    """``sg.batch.run`` on a warmed local cluster of ``workers`` workers.

    Returns its BatchReport, the CPU time (s) of the workers during the run, and that of
    this process (the client, with the local cluster's scheduler).
    """
    from distributed import Client

    with local_cluster(workers) as cluster, Client(cluster) as client:
        client.run(warm_up)
        before, cpu = client.run(time.process_time), time.process_time()
        report = sg.batch.run(objects, GRASPS, out, scheduler=cluster.scheduler_address, progress=False)
        cpu, after = time.process_time() - cpu, client.run(time.process_time)
    return report, sum(after[w] - before[w] for w in before), cpu


def content(path):
    """A result file's content without its timings (``time_s``, the reach's ``cpu_time``), as JSON text."""
    data = json.loads(Path(path).read_text())
    data.pop("time_s", None)
    if isinstance(data.get("reach"), dict):
        data["reach"].pop("cpu_time", None)
    return json.dumps(data, sort_keys=True)


def results(out):
    """Result, validation and failure files under ``out``, relative paths."""
    return sorted(p.relative_to(out).as_posix() for p in Path(out).glob("results/**/*.json")
                  if p.name != "object.json" and not p.name.startswith("."))  # not temporary files


def differing(a, b):
    """Result files of ``a`` that differ in ``b`` but for their timings (or that ``b`` lacks)."""
    return [name for name in results(a) if not (Path(b) / name).is_file() or content(Path(a) / name) != content(Path(b) / name)]


def interrupt_check(objects, reference, out):
    """Kill ``synergrasp batch`` part way, rerun it; compare with ``reference``. Returns (killed_at, verdict, text)."""
    command = [sys.executable, "-m", "synergrasp.cli", "batch", *map(str, objects), "--grasp", *GRASPS,
               "--out", str(out), "--workers", "2", "--quiet"]
    total = len(results(reference))
    first = subprocess.Popen(command, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                             start_new_session=True)
    while len(results(out)) < max(1, total // 3) and first.poll() is None:
        time.sleep(0.01)
    os.killpg(first.pid, signal.SIGKILL)  # the client and its workers at once
    first.wait()
    killed_at = len(results(out))
    rerun = subprocess.run(command, cwd=ROOT, capture_output=True, text=True)
    names, expected = set(results(out)), set(results(reference))
    with open(Path(out) / "summary.csv", newline="") as handle:
        rows = [(r["object"], r["grasp"]) for r in csv.DictReader(handle)]
    leftovers = [p for p in Path(out).rglob(".*") if p.name != ".lock"]  # the run's lock file stays
    counts = {
        "missing": len(expected - names), "extra": len(names - expected), "differing": len(differing(out, reference)),
        "duplicated rows": len(rows) - len(set(rows)), "temporary files": len(leftovers),
    }
    ok = rerun.returncode == 0 and 0 < killed_at < total and not any(counts.values()) and len(rows) == total
    text = (f"killed after {killed_at} of {total} results; rerun (exit {rerun.returncode}): {len(names)} results, "
            + ", ".join(f"{v} {k}" for k, v in counts.items()) + f", summary {len(rows)} rows")
    return killed_at, "PASS" if ok else "FAIL", text


def loop_cost(quick, out, trim):
    """CPU time (s) and minor page faults of the loop in a fresh process, with ``MALLOC_TRIM_THRESHOLD_`` = ``trim``."""
    env = {k: v for k, v in os.environ.items() if k != "MALLOC_TRIM_THRESHOLD_"}
    if trim is not None:
        env["MALLOC_TRIM_THRESHOLD_"] = str(trim)
    shutil.rmtree(out, ignore_errors=True)
    done = subprocess.run([sys.executable, __file__, "--loop-cost", str(out), "--out", str(Path(out).parent),  # (not
                           *(["--quick"] if quick else [])],  # the default --out, which argparse would create)
                          env=env, capture_output=True, text=True, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="the three built-ins only (6 plans)")
    parser.add_argument("--out", type=output_folder, default="bench-out/batch", help="output folder (default bench-out/batch)")
    parser.add_argument("--loop-cost", metavar="DIR", help=argparse.SUPPRESS)  # step 6, in a fresh process
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore")
    objects = BUILTINS if args.quick else [*sorted(MESHES.glob("*.stl")), *BUILTINS]  # not the random_urdfs folder
    tasks = expand(objects, GRASPS)
    if args.loop_cost:
        warm_up()
        cpu, faults = time.process_time(), resource.getrusage(resource.RUSAGE_SELF).ru_minflt
        loop(tasks, args.loop_cost)
        print(json.dumps([time.process_time() - cpu, resource.getrusage(resource.RUSAGE_SELF).ru_minflt - faults]))
        return
    out = args.out.resolve()  # the timed child runs in the repository's folder
    for name in ("loop", "dask-1", "dask-2", "interrupted", "malloc"):
        shutil.rmtree(out / name, ignore_errors=True)
    for task in tasks:  # fill the decomposition cache before any clock starts
        load_object(task.source)
    warm_up()
    load_before = os.getloadavg()[0]
    print(f"machine: {os.cpu_count()} CPUs, load average {load_before:.2f} before")
    print(f"tasks: {len(tasks)} ({len(tasks) // len(GRASPS)} objects x {', '.join(GRASPS)})")

    cpu = time.process_time()
    loop_s, client_s = loop(tasks, out / "loop")
    cpu = time.process_time() - cpu
    print(f"loop (in-process):  wall {loop_s:7.2f} s, {len(tasks) / loop_s:.3f} plans/s, CPU {cpu:.2f} s: "
          f"{len(tasks) / cpu:.3f} plans per CPU second; writing and reading back a result: "
          f"{1e3 * client_s / len(tasks):.1f} ms CPU")
    walls, cpus = {}, {}
    for workers in (1, 2):
        report, worker_cpu, client_cpu = on_dask(objects, workers, out / f"dask-{workers}")
        walls[workers], cpus[workers] = report.wall_s, worker_cpu + client_cpu
        print(f"dask, {workers} worker{'s' if workers > 1 else ' '}:    wall {report.wall_s:7.2f} s, "
              f"{report.finished / report.wall_s:.3f} plans/s, CPU {worker_cpu:.2f} s in the workers "
              f"+ {client_cpu:.2f} s in the client")
    ratio = walls[1] / walls[2]
    print(f"throughput 2 workers / 1 worker: {ratio:.2f}x (target >= 1.6: {'met' if ratio >= 1.6 else 'NOT met'})")
    extra = walls[1] - loop_s
    overhead = extra / loop_s
    print(f"overhead dask (1 worker) against the loop: {extra:+.2f} s over {len(tasks)} tasks = "
          f"{1e3 * extra / len(tasks):+.1f} ms per task, {100 * overhead:+.1f} % "
          f"(target <= 10 %: {'met' if overhead <= 0.10 else 'NOT met'})")
    extra = cpus[1] - cpu
    print(f"CPU overhead dask (1 worker, workers + client) against the loop: {extra:+.2f} s = "
          f"{1e3 * extra / len(tasks):+.1f} ms per task, {100 * extra / cpu:+.1f} %")
    diff = sorted(set(differing(out / "loop", out / "dask-1") + differing(out / "loop", out / "dask-2")))
    print(f"same result per task, bit for bit but for the timings (loop, 1 worker, 2 workers): "
          f"{'yes' if not diff else 'NO'} ({len(tasks) - len(diff)} of {len(tasks)})"
          + (f"; differ: {', '.join(diff)}" if diff else ""))
    _, verdict, text = interrupt_check(objects, out / "dask-2", out / "interrupted")
    print(f"interrupt and rerun: {text}: {verdict}")
    (cpu_trim, faults_trim), (cpu, faults) = (loop_cost(args.quick, out / "malloc", t) for t in (65536, None))
    print(f"loop with Dask's MALLOC_TRIM_THRESHOLD_=65536: CPU {cpu_trim:.2f} s, {faults_trim} minor page faults; "
          f"without: CPU {cpu:.2f} s, {faults} page faults ({100 * (cpu_trim / cpu - 1):+.0f} % CPU with it)")
    print(f"load average after: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
