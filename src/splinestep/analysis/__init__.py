"""The analysis of the method, apart from the solver: the sympy derivations
(``theory``), the conjugacy to Stormer-Verlet (``conjugacy``), the splines
of higher degree (``higher_degree``), Richardson extrapolation
(``extrapolation``), and the measurements the notebooks make: rates and
fits (``diagnostics``), where the cannonball's error is made
(``error_location``), long runs (``long_time``), adaptive knots
(``adaptive``), what rtol bounds (``tolerance``), the compositions' orders
and cost (``composition``), Newmark's family (``family``) and the
step-too-large check's record (``alarms``).

The notebooks use these modules; the solver (``splinestep.solve`` and the
modules it is built from) never imports them, so ``import splinestep``
imports no sympy.
"""

import importlib

# The extra that installs each optional dependency of these modules
# (pyproject.toml's [project.optional-dependencies]).
EXTRAS = {"pandas": "analysis", "sympy": "analysis"}


def require(name, user):
    """Import the optional dependency ``name`` for the module ``user``, or
    raise an ImportError that names the extra installing it."""
    try:
        return importlib.import_module(name)
    except ImportError as error:
        extra = EXTRAS[name]
        raise ImportError(
            f"{user} needs {name}, which `pip install splinestep` does not install; "
            f"install it with `pip install 'splinestep[{extra}]'` (from a clone: "
            f"`pip install '.[{extra}]'`; or `pip install {name}`)"
        ) from error
