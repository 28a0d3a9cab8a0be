"""The tolerances shared by several modules of the library, each defined here once.

The geometry's and the LP layer's tests of computed numbers (is an LP basis
degenerate, are two values equal, does a bound prune) use these. A
tolerance that belongs to one module's own algorithm is defined there,
beside it (the native simplex's `synergrasp.lp.native.TOL`, the force-closure
test's `synergrasp.quality.FORCE_CLOSURE_TOL`).
"""

#: Relative tolerance within which two computed values (LP values, bounds, facet planes) are
#: taken as equal, or a value as zero: ``|a - b| <= VALUE_TOL * (1 + |a|)``.
VALUE_TOL = 1e-9

#: Tolerance on primal weights and reduced costs in the degeneracy test of an LP optimum (a
#: weight above ``DEGENERACY_TOL * max(1, max weight)`` is positive, a reduced cost within it is 0).
DEGENERACY_TOL = 1e-7
