"""The numerical tolerances of the library, each defined here once.

Every test that decides something from computed numbers (is an LP basis
degenerate, are two values equal, does a bound prune) uses one of these.
"""

#: Relative tolerance within which two computed values (LP values, bounds, facet planes) are
#: taken as equal, or a value as zero: ``|a - b| <= VALUE_TOL * (1 + |a|)``.
VALUE_TOL = 1e-9

#: Tolerance on primal weights and reduced costs in the degeneracy test of an LP optimum (a
#: weight above ``DEGENERACY_TOL * max(1, max weight)`` is positive, a reduced cost within it is 0).
DEGENERACY_TOL = 1e-7
