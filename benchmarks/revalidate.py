"""Validate a physics study's plans again with the current code, and compare with the verdicts it stored.

Usage::

    python benchmarks/revalidate.py DIR [--set paper household test] [--variants synergrasp dexgraspbench]

``DIR`` is the ``--out`` folder of an earlier ``python benchmarks/physics_study.py`` run: for every
case of the chosen sets whose plan it saved (``DIR/cases/<case>/plan.json``), each chosen variant of
the study's validations is run again, and its verdict and CPU time are set beside the ones saved
there. Prints the cases whose outcome changed and, per variant, how many were held before and now
and the CPU time in all: what a change of the simulation or of the protocol's implementation does to
the verdicts, on the same plans (no replanning, so no plan changes between the two).
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import synergrasp as sg

sys.path.insert(0, str(Path(__file__).resolve().parent))
from physics_study import GRASPS, VARIANTS, case_folder, object_sets, variant_file  # noqa: E402


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("folder", type=Path, help="the --out folder of a physics_study.py run")
    parser.add_argument("--set", nargs="+", choices=["paper", "household", "test"],
                        default=["paper", "household", "test"],
                        help="object sets of the study whose saved plans are validated again")
    parser.add_argument("--variants", nargs="+", choices=sorted(VARIANTS),
                        default=["synergrasp", "dexgraspbench"],
                        help="the study's validations to run again (physics_study.VARIANTS)")
    args = parser.parse_args(argv)
    if not args.folder.is_dir():
        parser.error(f"{args.folder} is not a folder: name the --out folder of a physics_study.py run")
    warnings.simplefilter("ignore")
    totals = {v: dict(cases=0, before=0, after=0, changed=0, cpu_before=0.0, cpu_after=0.0) for v in args.variants}
    for group, objects in object_sets(args.set).items():
        for name, obj in objects.items():
            for grasp in GRASPS:
                folder = case_folder(args.folder, group, name, grasp)
                if not (folder / "plan.json").exists():
                    continue
                result = sg.PlanResult.load(folder / "plan.json")
                for variant in args.variants:
                    stored = folder / variant_file(variant)
                    if not stored.exists():  # the study could not validate this plan (not a grasp)
                        continue
                    before = sg.Validation.load(stored)
                    start = time.process_time()
                    after = sg.validate(result, obj, **VARIANTS[variant])
                    cpu = time.process_time() - start
                    t = totals[variant]
                    t["cases"] += 1
                    t["before"] += before.held
                    t["after"] += after.held
                    t["cpu_before"] += before.cpu_time
                    t["cpu_after"] += cpu
                    if (before.held, before.outcome) != (after.held, after.outcome):
                        t["changed"] += 1
                        print(f"{group} {name} {grasp} [{variant}]: {before.outcome} -> {after.outcome}  "
                              f"({before.reason[:70]} -> {after.reason[:70]})", flush=True)
    if not any(t["cases"] for t in totals.values()):
        raise SystemExit(f"{args.folder} holds no validated plan of the sets {args.set}: name the --out folder of a "
                         "physics_study.py run of those sets")
    for variant, t in totals.items():
        print(f"{variant}: {t['cases']} validations, held {t['before']} before and {t['after']} now, "
              f"{t['changed']} outcomes changed; CPU {t['cpu_before']:.1f} s before, {t['cpu_after']:.1f} s now")


if __name__ == "__main__":
    main()
