"""Solver comparison experiments for synergrasp (not part of the installed library).

* ``python -m solvers.compare [--quick] [--out DIR] [--docs]`` times and
  cross-checks every LP backend plus two references (``scipy.optimize.linprog``
  and a plain cvxpy model) on the LPs synergrasp solves, from one LP to whole plans.
* ``python -m solvers.profile_plan [--quick] [--out DIR] [--docs]`` plans the paper's 8
  cases with the package of this checkout and of an earlier commit and compares their time
  per iteration and the LP solver's share of it.

The reference backends live in :mod:`solvers.references`.
"""
