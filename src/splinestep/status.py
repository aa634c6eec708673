"""The status codes of every step loop, in one table.

A compiled loop cannot raise with a message, so it returns what went wrong
as a code; the drivers turn the code into the result's ``status`` (0
finished, 1 a terminal event, -1 failed) and a ``message``.  Each code
means one thing on every path: :data:`CODES` lists them, and
``tests/test_scipy_ivp_ported.py`` checks that they are distinct.
"""

# The step itself (every path).
OK = 0
NOT_CONVERGED = 1        # the step equation's iteration ran out of iterations
NON_FINITE = 2           # fun returned a value that is not finite
BAD_SHAPE = 3            # fun returned an array of the wrong shape
SINGULAR = 4             # the Newton matrix is singular
DIVERGED = 5             # an iterate of y or y' is not finite
# The drivers.
STEP_TOO_SMALL = 10      # adaptive knots: the step fell below the rounding of t
TOO_MANY_STEPS = 11      # adaptive knots, reversible steps: max_steps reached
RHO_NOT_POSITIVE = 20    # reversible steps: the control variable left (0, inf)

CODES = {name: value for name, value in globals().items()
         if name.isupper() and isinstance(value, int)}
