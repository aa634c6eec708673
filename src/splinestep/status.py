"""The status codes of the step loop, in one table, with what each means.

The compiled driver (:mod:`splinestep.driver`) cannot raise with a message,
so it returns what happened as a code; :func:`message` turns the code into
the result's ``message``, and the result's ``status`` is 0 (finished), 1 (a
terminal event stopped the run) or -1 (failed).  Each code means one thing
on every path: :data:`CODES` lists them, and
``tests/test_scipy_ivp_ported.py`` checks that they are distinct and that
each failure has its sentence.
"""

# The step itself (every step of every method).
OK = 0
NOT_CONVERGED = 1        # the step equation's iteration ran out of iterations
NON_FINITE = 2           # fun returned a value that is not finite
BAD_SHAPE = 3            # fun returned an array of the wrong shape
SINGULAR = 4             # the Newton matrix is singular
DIVERGED = 5             # an iterate of y or y' is not finite
GREW = 6                 # the sweep's change grew in two iterations in a row
TOO_SLOW = 7             # the sweep contracts too slowly to converge in max_iter
# The driver and its step-size controllers.
STEP_TOO_SMALL = 10      # error control: the step fell below the rounding of t
TOO_MANY_STEPS = 11      # max_steps step attempts made before the end
TERMINAL_EVENT = 12      # a terminal event stopped the run (not a failure)
EVENT_FAILED = 13        # an event function raised (re-raised by the front door)
OUT_OF_MEMORY = 14       # storing every knot would take more memory than is free
EXCEEDED = 15            # |y| exceeded the bound y_max at a knot
RHO_NOT_POSITIVE = 20    # time-reversible steps: the control variable left (0, inf)

CODES = {name: value for name, value in globals().items()
         if name.isupper() and isinstance(value, int)}

# What a failed step means, for a message.
FAILURES = {
    NOT_CONVERGED: "the iteration did not converge in {max_iter} iterations",
    NON_FINITE: "the right-hand side returned a value that is not finite",
    BAD_SHAPE: "the right-hand side returned an array of the wrong shape "
               "(expected shape ({m},))",
    SINGULAR: "the Newton matrix is singular or its solution is not finite",
    DIVERGED: "the iteration diverged (an iterate of y or y' is not finite)",
    GREW: "the iteration diverged (its change grew in two iterations in a row)",
    TOO_SLOW: "the iteration contracted too slowly to converge in {max_iter} iterations",
}

# What to try when a step fails, appended to the message.
CONDITION = ("beta h^2 |dF/dy| + gamma h |dF/dyp| < 1 (h^2/6 and h/2 for the spline; "
             "times (1 - alpha_f)/(1 - alpha_m) for the alpha members)")
# A sweep whose change shrinks by more than this factor per iteration
# contracts too slowly to be worth more iterations.
SLOW_SWEEP = 0.9
HINTS = {
    SINGULAR: " Try a smaller h: the step equation may have no solution at this h.",
    NON_FINITE: " The solution may blow up here, or the step may be too large.",
    DIVERGED: " Try a smaller h, or, after the fixed-point sweep, iteration=\"newton\" "
              f"(the sweep converges when {CONDITION}).",
}


def not_converged_hint(rate, sweep):
    """What to try when a step's iteration ran out of iterations, from
    ``rate``, its change's mean factor per iteration (NaN when unknown):
    the sweep's contraction condition is blamed only when the sweep did
    not contract (rate >= 1)."""
    if rate != rate:   # NaN: fewer than two iterations
        return " Try a larger max_iter."
    if not sweep:
        return (f" Newton's update changed by a factor of about {rate:.2g} per iteration. "
                "Try a smaller h: the step equation may have no solution near this guess.")
    if rate >= 1.0:
        return (f" The sweep did not contract (its change grew by a factor of about "
                f"{rate:.3g} per iteration): it converges when {CONDITION}. Try a "
                "smaller h, or iteration=\"newton\".")
    if rate >= SLOW_SWEEP:
        return (f" The sweep contracted only slowly (its change shrank by a factor of about "
                f"{rate:.3g} per iteration: {CONDITION} barely holds). Try a smaller h, "
                "iteration=\"newton\", or a larger max_iter.")
    return (f" The sweep contracted (its change shrank by a factor of about {rate:.2g} per "
            f"iteration, so {CONDITION} holds) but did not reach tol in max_iter iterations: "
            "raise max_iter (or tol), or try iteration=\"newton\".")

SUCCESS = "The solver successfully reached the end of the integration interval."


def short(t):
    """A time for a message: the shortest repr of ``t`` to 10 digits."""
    return f"{t:.10g}"


# The codes a plain fun's or jac's refused value produces: only these take
# the front door's more precise reason.
REFUSED = (BAD_SHAPE, SINGULAR)


def failure(code, max_iter, m, reason=None):
    """What a failed step's ``code`` means (``reason``, when the front door
    knows more precisely what ``fun`` or ``jac`` returned, replaces the
    generic text of the codes in :data:`REFUSED`)."""
    if reason is not None and code in REFUSED:
        return reason
    return FAILURES[code].format(max_iter=max_iter, m=m)


def hint(code, rate, sweep):
    """The advice appended to the message of a step that failed with
    ``code`` (``rate`` and ``sweep`` as for :func:`not_converged_hint`)."""
    if code in (NOT_CONVERGED, GREW, TOO_SLOW):
        return not_converged_hint(rate, sweep)
    return HINTS.get(code, "")


def message(run, max_iter, m, max_steps, reason=None, sweep=False, y_max=float("inf")):
    """The result's message for the driver's output ``run``
    (:class:`splinestep.driver.Run`); ``sweep`` when its steps were solved
    by the fixed-point sweep, ``y_max`` the run's bound on |y|."""
    code = run.status
    if code == OK:
        return SUCCESS
    if code == TERMINAL_EVENT:
        return f"A termination event occurred at t = {short(run.t_last)}."
    if run.fail_step == 0:
        return (f"The initial evaluation at t = {short(run.t_fail)} failed: "
                f"{failure(code, max_iter, m, reason)}.")
    accepted = f"Returning the {run.nstep} steps completed before it."
    if code == TOO_MANY_STEPS:
        return (f"The run stopped at t = {short(run.t_last)} after max_steps = {max_steps} "
                f"step attempts. {accepted}")
    if code == OUT_OF_MEMORY:
        return (f"The run stopped at t = {short(run.t_last)}: storing every knot would take more "
                f"than a fifth of the memory free at its start ({run.n_knots} knots of {m} "
                f"components stored, {run.n_knots * (3 * m + 2) * 8 / 2**30:.3g} GiB). Pass "
                f"t_eval, without dense_output, to keep only the values at the times needed. "
                f"{accepted}")
    if code == EXCEEDED:
        return (f"The run stopped at t = {short(run.t_fail)}: |y| exceeded y_max = "
                f"{y_max:.6g} there. {accepted}")
    if code == RHO_NOT_POSITIVE:
        return (f"The control variable rho is not positive (or not finite) at "
                f"t = {short(run.t_last)}: eps is too large for this control, or the control "
                f"returned a value that is not finite. {accepted}")
    if code == STEP_TOO_SMALL:
        last = run.last_status
        why = ("its error estimate was too large (if F jumps there, as a forcing switched "
               "on does, the spline, whose y'' is continuous, cannot follow it: end t_span at "
               "the jump and start a new run from the state there, each run with F's values on "
               "its side of the jump)" if last == OK else
               f"its equation could not be solved ({failure(last, max_iter, m, reason)})")
        return (f"The step size fell below the rounding floor at t = {short(run.t_last)}: the "
                f"last step tried was rejected because {why}. {accepted}")
    return (f"Step {run.fail_step} (from t = {short(run.t_last)} to t = {short(run.t_fail)}) "
            f"failed: {failure(code, max_iter, m, reason)}. {accepted}"
            f"{hint(code, run.rate, sweep) if reason is None or code not in REFUSED else ''}")
