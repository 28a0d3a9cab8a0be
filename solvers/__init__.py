"""Solver comparison experiments for synergrasp (not part of the installed library).

* ``python -m solvers.compare [--quick] [--out solvers/results] [--docs]`` times and
  cross-checks every LP backend plus two references (``scipy.optimize.linprog``
  and a plain cvxpy model) on the LPs synergrasp solves, from one LP to whole plans.
* ``python -m solvers.profile_plan`` profiles one plan and records before/after
  numbers of the overhead work around the solver.

The reference backends live in :mod:`solvers.references`.
"""
