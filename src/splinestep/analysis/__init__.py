"""The analysis of the method, apart from the solver: the sympy derivations
(``theory``), the measurements of rates and fits (``diagnostics``), the
conjugacy to Stormer-Verlet (``conjugacy``), the splines of higher degree
(``higher_degree``) and Richardson extrapolation (``extrapolation``).

The notebooks use these modules; the solver (``splinestep.solve`` and the
modules it is built from) never imports them, so ``import splinestep``
imports no sympy.
"""
