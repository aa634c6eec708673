"""The analysis of the method, apart from the solver: the sympy derivations
(``theory``), the conjugacy to Stormer-Verlet (``conjugacy``), the splines
of higher degree (``higher_degree``), Richardson extrapolation
(``extrapolation``), and the measurements the notebooks make: rates and
fits (``diagnostics``), where the cannonball's error is made
(``error_location``), long runs (``long_time``), adaptive knots
(``adaptive``), what rtol bounds (``tolerance``) and the step-too-large
check's record (``alarms``).

The notebooks use these modules; the solver (``splinestep.solve`` and the
modules it is built from) never imports them, so ``import splinestep``
imports no sympy.
"""
