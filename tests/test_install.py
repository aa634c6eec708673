"""The package as a library a user installs: what a missing optional
dependency says, and what the base install needs."""

import subprocess
import sys
import textwrap

import pytest


def run_without(module, code):
    """Run ``code`` in a new interpreter in which ``module`` cannot be imported."""
    script = f"import sys; sys.modules[{module!r}] = None\n" + textwrap.dedent(code)
    return subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)


@pytest.mark.parametrize("module, user", [("pandas", "tolerance"), ("sympy", "theory"),
                                          ("sympy", "family"), ("pandas", "long_time")])
def test_a_missing_extra_is_named_with_the_command_that_installs_it(module, user):
    done = run_without(module, f"from splinestep.analysis import {user}")
    assert done.returncode != 0
    last = done.stderr.strip().splitlines()[-1]
    assert last.startswith("ImportError: splinestep.analysis." + user + f" needs {module}")
    assert "pip install 'splinestep[analysis]'" in last


def test_the_solver_needs_no_extra():
    """numpy, scipy and numba only: without pandas, sympy and matplotlib
    the solver imports and solves."""
    done = run_without("pandas", """
        sys.modules["sympy"] = sys.modules["matplotlib"] = None
        import numpy as np, splinestep
        res = splinestep.solve(lambda t, y, yp: -y, (0.0, 1.0), [1.0], [0.0], h=0.01)
        print(res.status, abs(res.y[0, -1] - np.cos(1.0)) < 1e-4)
        """)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["0", "True"]


def test_a_numba_without_the_cache_parts_splinestep_extends_is_refused_by_name():
    """splinestep extends numba's on-disk cache through names not all of
    which are public: a numba without one of them is refused at import,
    naming it."""
    script = textwrap.dedent("""
        import numba.core.caching as caching
        del caching.CacheImpl._locator_classes
        import splinestep
        """)
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    last = done.stderr.strip().splitlines()[-1]
    assert last.startswith("ImportError: splinestep extends numba's on-disk cache"), last
    assert "numba.core.caching.CacheImpl._locator_classes;" in last


def test_the_compiled_loops_are_cached_in_the_user_cache_folder_not_beside_the_source(tmp_path):
    """A solve in a new process writes numba's cache of the package's loops
    below SPLINESTEP_CACHE_DIR/loops and nothing into the package's folder."""
    import os
    from pathlib import Path

    import splinestep
    package = Path(splinestep.__file__).parent
    before = {p for p in package.rglob("*") if p.suffix in (".nbi", ".nbc")}
    env = dict(os.environ, SPLINESTEP_CACHE_DIR=str(tmp_path / "cache"))
    script = ("import splinestep; splinestep.solve(lambda t, y, yp: -y, (0.0, 1.0), [1.0], "
              "[0.0], h=0.1)")
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, env=env)
    assert done.returncode == 0, done.stderr
    after = {p for p in package.rglob("*") if p.suffix in (".nbi", ".nbc")}
    assert after == before
    written = list((tmp_path / "cache" / "loops").rglob("*.nbi"))
    assert any("driver" in p.name for p in written), written


def test_solve_shows_its_options_in_its_signature():
    """help(), IDEs and the API page read the options from the signature:
    every option of solve is a keyword-only parameter with its default."""
    import inspect

    import splinestep
    from splinestep import spline
    parameters = inspect.signature(splinestep.solve).parameters
    for name, default in spline._OPTIONS.items():
        assert parameters[name].kind is inspect.Parameter.KEYWORD_ONLY, name
        # the adaptive options default to None ("not given"), resolved to _OPTIONS' values
        expected = None if name in spline.ADAPTIVE_ONLY else default
        assert parameters[name].default is expected or parameters[name].default == expected, name


@pytest.mark.parametrize("grid", [dict(h=0.1), dict(knots=[0.0, 0.3, 1.0])])
def test_a_tolerance_given_with_a_fixed_grid_is_said_to_be_ignored(grid):
    import warnings

    import numpy as np

    import splinestep
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        bounded = splinestep.solve(lambda t, y, yp: -y, (0.0, 1.0), 1.0, 0.0, rtol=1e-8,
                                   atol=1e-9, check=False, **grid)
    said = [str(w.message) for w in caught if "adaptive knots only" in str(w.message)]
    assert said == ["rtol and atol apply to adaptive knots only (neither h nor knots given) "
                    "and are ignored with a fixed grid"]
    plain = splinestep.solve(lambda t, y, yp: -y, (0.0, 1.0), 1.0, 0.0, check=False, **grid)
    np.testing.assert_array_equal(bounded.y, plain.y)   # ignored indeed
    with pytest.raises(ValueError, match="unknown options \\['rtl'\\]"):
        splinestep.solve(lambda t, y, yp: -y, (0.0, 1.0), 1.0, 0.0, rtl=1e-8, **grid)


def test_a_long_compilation_is_said_once_and_a_short_one_or_a_quiet_run_not(capsys, monkeypatch):
    """One line on stderr when numba's compiling (or loading) takes longer
    than COMPILE_NOTICE_AFTER: once per process, never for a fast load,
    never with SPLINESTEP_QUIET=1."""
    import time

    from splinestep import _adapters
    monkeypatch.setattr(_adapters, "COMPILE_NOTICE_AFTER", 0.05)
    monkeypatch.setattr(_adapters, "_NOTICED", [])
    monkeypatch.delenv("SPLINESTEP_QUIET", raising=False)
    with _adapters.compiling_notice():
        pass                                       # a load from the cache: silent
    time.sleep(0.2)
    assert capsys.readouterr().err == ""
    monkeypatch.setenv("SPLINESTEP_QUIET", "1")
    with _adapters.compiling_notice():
        time.sleep(0.2)                            # long, but asked to be quiet
    assert capsys.readouterr().err == ""
    monkeypatch.delenv("SPLINESTEP_QUIET")
    for _ in range(2):
        with _adapters.compiling_notice():
            time.sleep(0.2)                        # long: said, the first time only
    said = capsys.readouterr().err.splitlines()
    assert len(said) == 1 and said[0].startswith("splinestep: numba is compiling"), said
    assert "SPLINESTEP_QUIET=1" in said[0]


def test_import_splinestep_leaves_the_test_problems_until_they_are_used():
    """``import splinestep`` loads the solver, not the report's test
    problems (their compiled right-hand sides cost most of a second to
    load); ``splinestep.problems`` and ``from splinestep import problems``
    still work."""
    script = textwrap.dedent("""
        import sys, splinestep
        print("splinestep.problems" in sys.modules)
        print(splinestep.problems.cannonball(0.6).h)
        from splinestep import problems
        print(problems is splinestep.problems, "splinestep.problems" in sys.modules)
        """)
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["False", "0.01", "True", "True"]


def test_the_import_graph_finds_imports_at_every_depth_of_statements(tmp_path):
    """The stamp of a compiled function covers the modules its module
    imports anywhere: in functions, conditionals, handlers and with-blocks
    (the walk visits statements only, not expressions)."""
    import ast

    from splinestep import _compile
    source = textwrap.dedent("""
        import os
        def f():
            from . import a
            if True:
                try:
                    import splinestep.b
                except ImportError:
                    from .c import d
                finally:
                    pass
            with open(os.devnull):
                from .e import g
        class K:
            def m(self):
                from . import h
        """)
    names = [getattr(n, "module", None) or n.names[0].name for n in
             _compile._import_statements(ast.parse(source))]
    assert sorted(names) == sorted(["os", "a", "splinestep.b", "c", "e", "h"])
