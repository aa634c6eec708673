"""Reference trajectories of the Newmark family from OpenSees.

Runs OpenSees's transient integrators (through openseespy) on three small
problems and writes, for each problem, every step of every member to
``tests/data/opensees/<case>.json``, so that a test can compare the
package's Newmark family with an independent code, member by member and
step by step.  Run from the repository root, with openseespy installed (not
a dependency of the package)::

    python scripts/opensees_reference.py

It prints, for each member and case, how far OpenSees is from a short numpy
implementation of the step written here (:func:`formula_run`), and writes
that number into the JSON.  Re-running writes the same bytes.

The members are written in Chung and Hulbert's (1993) convention
(alpha_m, alpha_f, beta, gamma): for M y'' = f(t) - C y' - R(y),

    y_{n+1}  = y_n + h y'_n + h^2 ((1/2 - beta) a_n + beta a_{n+1})
    y'_{n+1} = y'_n + h ((1 - gamma) a_n + gamma a_{n+1})
    M ((1 - alpha_m) a_{n+1} + alpha_m a_n)
        = f(t_{n+1} - alpha_f h) - C y'_{n+1-alpha_f} - R(y_{n+1-alpha_f}),

with x_{n+1-alpha_f} = (1 - alpha_f) x_{n+1} + alpha_f x_n and
a_0 = M^-1 (f(t_0) - C y'_0 - R(y_0)).

Notes
-----
Facts about OpenSees 3.7.1 (openseespy 3.7.1.2) this relies on, read in its
source (``SRC/analysis/integrator``, ``SRC/domain/pattern``) and checked by
the runs:

* openseespy's Linux wheel loads the system's BLAS and LAPACK: on Debian,
  ``apt-get install libblas3 liblapack3``.
* Every integrator starts from the committed nodal acceleration, zero unless
  set: a_0 is given with ``setNodeAccel(node, dof, a0, '-commit')`` (y_0 and
  y'_0 with ``setNodeDisp`` and ``setNodeVel``).
* Stiffness-proportional Rayleigh damping reaches a ``zeroLength`` element
  only when it is built with ``-doRayleigh 1``; the mass-proportional part
  acts at the nodes.  ``rayleigh(a0, a1, 0, 0)`` gives C = a0 M + a1 K.
* A ``Path`` time series returns 0 after its last point unless given
  ``-useLast`` (then it holds the last value); between points it
  interpolates linearly, a_g(t) = v_k + (v_{k+1} - v_k) (t/dt - k) with
  k = floor(t/dt).  ``UniformExcitation`` adds -M 1 a_g(t) to the load.
* ``Trig`` with tStart = 0 is f(t) = cFactor sin(2 pi t / period).
* OpenSees's alphas are one minus Chung and Hulbert's.  ``HHT`` takes
  alpha_OS = 1 - alpha_f (then gamma = 3/2 - alpha_OS and
  beta = (2 - alpha_OS)^2/4); ``HHTGeneralized`` takes
  (1 - alpha_m, 1 - alpha_f, beta, gamma), or rho_inf alone.  Both take the
  load at t_n + alpha_OS h = t_{n+1} - alpha_f h, damping and restoring
  force at the weighted state, inertia at (1 - alpha_m) a_{n+1} + alpha_m a_n
  (HHT: a_{n+1}).  The time is accumulated, t_n + alpha_OS h then
  + (1 - alpha_OS) h, and drifts from t_0 + n h by rounding (4e-14 at
  t = 4 for HHT); the JSON keeps OpenSees's t.
* ``GeneralizedAlpha`` (alphaM_OS, alphaF_OS) weights the inertia in its
  tangent but hands the nodes a_{n+1}, so its converged steps solve
  M a_{n+1} = f - C y'_{n+1-alpha_f} - R(y_{n+1-alpha_f}): the formula with
  alpha_m = 0 and beta, gamma kept at the generalized-alpha values, which is
  first order (it agrees with that to 4e-12 to 5e-11, its inconsistent
  tangent making Newton's method converge linearly).  Its four-number form
  reads (alphaM, alphaF, beta, gamma), not the (alphaM, alphaF, gamma, beta)
  of its usage message.
  ``HHTGeneralized`` is the generalized-alpha member here.
* ``CentralDifference`` starts from y_{-1} = y_0 (it ignores y'_0 and a_0)
  and reports y'_{n+1} = (3 y_{n+1} - 4 y_n + y_{n-1}) / (2 h) and
  y''_{n+1} = (y'_{n+1} - y'_n) / h.  Its displacement recurrence is
  Newmark's with beta = 0 (damping at (y_{n+1} - y_{n-1}) / (2 h)), its start
  and its velocities are not.  ``Newmark 0.5 0.0 -form A`` (the acceleration
  as unknown) is the Newmark beta = 0 step and is the central-difference
  member here.  :func:`checks` prints how far both left-out integrators are
  from the formula.

Every analysis uses a full LAPACK system (``FullGeneral``), Newton's method
and the test NormDispIncr 1e-14 (50 iterations); ``CentralDifference``, which
accepts one iteration only, the linear algorithm.

References
----------
J. Chung and G. M. Hulbert, "A time integration algorithm for structural
dynamics with improved numerical dissipation: the generalized-alpha
method", J. Appl. Mech. 60 (1993) 371-375.

H. M. Hilber, T. J. R. Hughes and R. L. Taylor, "Improved numerical
dissipation for time integration algorithms in structural dynamics",
Earthquake Eng. Struct. Dyn. 5 (1977) 283-292.
"""

import json
import math
from pathlib import Path

import numpy as np
import openseespy.opensees as ops

OUT = Path(__file__).resolve().parent.parent / "tests" / "data" / "opensees"
N_STEPS = 200
TOLERANCE, MAX_ITERATIONS = 1e-14, 50


def member(alpha_m, alpha_f, beta, gamma, command):
    """A member's parameters and the OpenSees integrator that runs it."""
    return {"alpha_m": alpha_m, "alpha_f": alpha_f, "beta": beta,
            "gamma": gamma, "command": command}


def generalized_alpha(rho):
    """Chung and Hulbert's parameters for the spectral radius ``rho``."""
    alpha_m, alpha_f = (2 * rho - 1) / (rho + 1), rho / (rho + 1)
    return (alpha_m, alpha_f, (1 - alpha_m + alpha_f) ** 2 / 4,
            0.5 - alpha_m + alpha_f)


HHT_ALPHA_F, RHO_INF = 0.1, 0.8
MEMBERS = {
    "linear acceleration": member(0.0, 0.0, 1 / 6, 0.5, ("Newmark", 0.5, 1 / 6)),
    "average acceleration": member(0.0, 0.0, 0.25, 0.5, ("Newmark", 0.5, 0.25)),
    "Fox-Goodwin": member(0.0, 0.0, 1 / 12, 0.5, ("Newmark", 0.5, 1 / 12)),
    "central difference": member(0.0, 0.0, 0.0, 0.5,
                                 ("Newmark", 0.5, 0.0, "-form", "A")),
    "HHT": member(0.0, HHT_ALPHA_F, (1 + HHT_ALPHA_F) ** 2 / 4,
                  0.5 + HHT_ALPHA_F, ("HHT", 1 - HHT_ALPHA_F)),
    "generalized-alpha": member(*generalized_alpha(RHO_INF),
                                ("HHTGeneralized", RHO_INF)),
}


def chain_matrices(springs, masses):
    """Mass and stiffness matrices of a fixed-free chain of springs."""
    n = len(masses)
    stiffness = np.zeros((n, n))
    for i, k in enumerate(springs):
        stiffness[i, i] += k
        if i > 0:
            stiffness[i - 1, i - 1] += k
            stiffness[i - 1, i] -= k
            stiffness[i, i - 1] -= k
    return np.diag(masses), stiffness


def sdof_case():
    """One mass on a damped linear spring, driven by a sine."""
    return {
        "description": "one DOF: M y'' = f(t) - C y' - K y, f(t) = amplitude "
                       "sin(2 pi t / period); C = 0.15 M (mass-proportional "
                       "Rayleigh damping)",
        "n_dof": 1, "springs": [50.0], "mass": [[2.0]], "damping": [[0.15 * 2.0]],
        "stiffness": [[50.0]], "rayleigh": [0.15, 0.0],
        "load": {"kind": "sine", "dof": 0, "amplitude": 3.0, "period": 0.7,
                 "formula": "f(t)[dof] = amplitude * sin(2 * pi * t / period)"},
        "nonlinear_spring": None,
        "y0": [0.01], "yp0": [-0.2], "t0": 0.0, "h": 0.02, "n_steps": N_STEPS,
    }


def ground_record():
    """The ground acceleration table: a decaying wiggle at dt = 0.05."""
    dt, count = 0.05, 41
    values = [round(2.5 * math.exp(-1.2 * k * dt)
                    * math.sin(2 * math.pi * k * dt / 0.45 + 0.6), 6)
              for k in range(count)]
    return dt, values


def chain_case():
    """Three masses in a fixed-free chain with Rayleigh damping, shaken at
    the ground."""
    springs, masses, (a0, a1) = [400.0, 300.0, 200.0], [1.0, 1.5, 0.8], (0.2, 0.002)
    mass, stiffness = chain_matrices(springs, masses)
    dt, values = ground_record()
    return {
        "description": "three masses in a fixed-free chain (springs[i] "
                       "joins DOF i-1, the ground for i = 0, and DOF i), "
                       "C = a0 M + a1 K (rayleigh = [a0, a1]), ground "
                       "acceleration a_g(t): M y'' = -M 1 a_g(t) - C y' - K y, "
                       "y relative to the ground",
        "n_dof": 3, "springs": springs, "mass": mass.tolist(),
        "damping": (a0 * mass + a1 * stiffness).tolist(),
        "stiffness": stiffness.tolist(), "rayleigh": [a0, a1],
        "load": {"kind": "ground acceleration", "dt": dt, "values": values,
                 "formula": "f(t) = -M @ ones * a_g(t), a_g(t) = v[k] + "
                            "(v[k+1] - v[k]) * (t/dt - k), k = floor(t/dt); "
                            "v[-1] after the table"},
        "nonlinear_spring": None,
        "y0": [0.0] * 3, "yp0": [0.0] * 3, "t0": 0.0, "h": 0.01,
        "n_steps": N_STEPS,
    }


def hardening_case():
    """Two masses, the first held by a piecewise-linear hardening spring."""
    strain = [-0.25, -0.125, -0.0625, 0.0, 0.0625, 0.125, 0.25]
    force = [-34.375, -9.375, -3.125, 0.0, 3.125, 9.375, 34.375]
    mass, stiffness = chain_matrices([0.0, 30.0], [1.0, 0.5])
    return {
        "description": "two DOF, undamped: M y'' = f(t) - K y - e_0 r(y_0); "
                       "r is elastic, piecewise linear through the points "
                       "(slopes 50, 100, 200 for |y_0| in [0, 0.0625], "
                       "[0.0625, 0.125], beyond), K the linear spring "
                       "springs[1] between DOF 0 and DOF 1; springs[0] is r",
        "n_dof": 2, "springs": [None, 30.0], "mass": mass.tolist(),
        "damping": np.zeros((2, 2)).tolist(), "stiffness": stiffness.tolist(),
        "rayleigh": [0.0, 0.0],
        "load": {"kind": "sine", "dof": 0, "amplitude": 10.0, "period": 0.9,
                 "formula": "f(t)[dof] = amplitude * sin(2 * pi * t / period)"},
        "nonlinear_spring": {
            "between": "ground and DOF 0", "strain": strain, "force": force,
            "formula": "r(y) = force[i] + s_i (y - strain[i]), s_i = "
                       "(force[i+1] - force[i]) / (strain[i+1] - strain[i]), "
                       "i the segment holding y, first and last extended"},
        "y0": [0.0, 0.0], "yp0": [0.3, 0.0], "t0": 0.0, "h": 0.01,
        "n_steps": N_STEPS,
    }


CASES = {"sdof": sdof_case, "damped-chain": chain_case,
         "hardening-spring": hardening_case}


def load_function(problem):
    """f(t) of the problem, as OpenSees evaluates it."""
    load, n = problem["load"], problem["n_dof"]
    if load["kind"] == "sine":
        unit = np.eye(n)[load["dof"]]
        return lambda t: unit * (load["amplitude"]
                                 * math.sin(2 * math.pi * t / load["period"]))
    values, dt = load["values"], load["dt"]
    inertia = -np.asarray(problem["mass"]) @ np.ones(n)

    def ground(t):
        k = math.floor(t / dt)
        if k + 1 >= len(values):
            return inertia * values[-1]
        return inertia * (values[k] + (values[k + 1] - values[k]) * (t / dt - k))
    return ground


def spring_law(spring):
    """r(y) and r'(y) of a piecewise-linear spring, computed as OpenSees's
    ElasticMultiLinear does: on the segment holding y, the first and last
    segments extended beyond the points."""
    strain, force = spring["strain"], spring["force"]

    def segment(y):
        i = int(np.searchsorted(strain, y, side="right")) - 1
        i = min(max(i, 0), len(strain) - 2)
        return i, (force[i + 1] - force[i]) / (strain[i + 1] - strain[i])

    def r(y):
        i, slope = segment(y)
        return force[i] + slope * (y - strain[i])
    return r, (lambda y: segment(y)[1])


def restoring_force(problem):
    """R(y) and its Jacobian."""
    stiffness, spring = np.asarray(problem["stiffness"]), problem["nonlinear_spring"]
    if spring is None:
        return (lambda y: stiffness @ y), (lambda y: stiffness)
    r, dr = spring_law(spring)
    unit = np.eye(problem["n_dof"])[0]
    return (lambda y: stiffness @ y + unit * r(y[0]),
            lambda y: stiffness + np.outer(unit, unit) * dr(y[0]))


def initial_acceleration(problem):
    """a_0 = M^-1 (f(t_0) - C y'_0 - R(y_0))."""
    force, _ = restoring_force(problem)
    y0, yp0 = np.asarray(problem["y0"]), np.asarray(problem["yp0"])
    rhs = (load_function(problem)(problem["t0"])
           - np.asarray(problem["damping"]) @ yp0 - force(y0))
    return np.linalg.solve(np.asarray(problem["mass"]), rhs)


def formula_run(problem, params, times=None):
    """The step of the module docstring, in numpy: t, y, y', y'' per step.
    Each step solves for a_{n+1} by Newton's method, until the tangent no
    longer changes: R is piecewise linear, so the last solve is then exact.
    The load is taken at t_n + (1 - alpha_f) h, with t_n = t0 + n h, or
    t_n = ``times[n]``."""
    am, af, beta, gamma = (params[k] for k in ("alpha_m", "alpha_f", "beta", "gamma"))
    mass, damping = np.asarray(problem["mass"]), np.asarray(problem["damping"])
    force, jacobian = restoring_force(problem)
    load, h = load_function(problem), problem["h"]
    y, v = np.asarray(problem["y0"], float), np.asarray(problem["yp0"], float)
    a = initial_acceleration(problem)
    out = [(problem["t0"], y, v, a)]
    if times is None:
        times = problem["t0"] + h * np.arange(problem["n_steps"] + 1)
    for n in range(problem["n_steps"]):
        t_af = times[n] + (1 - af) * h
        y_pred, v_pred = y + h * v + h * h * (0.5 - beta) * a, v + h * (1 - gamma) * a
        x, used = a.copy(), None
        for _ in range(MAX_ITERATIONS):
            y1, v1 = y_pred + beta * h * h * x, v_pred + gamma * h * x
            ya, va = (1 - af) * y1 + af * y, (1 - af) * v1 + af * v
            tangent = ((1 - am) * mass + (1 - af) * gamma * h * damping
                       + (1 - af) * beta * h * h * jacobian(ya))
            if used is not None and np.array_equal(tangent, used):
                break
            residual = (mass @ ((1 - am) * x + am * a) - load(t_af)
                        + damping @ va + force(ya))
            x, used = x - np.linalg.solve(tangent, residual), tangent
        else:
            raise RuntimeError(f"no convergence at step {n + 1}")
        y, v, a = y_pred + beta * h * h * x, v_pred + gamma * h * x, x
        out.append((times[n + 1], y, v, a))
    return [np.array(column) for column in zip(*out)]


def build_model(problem):
    """The problem as an OpenSees model: node 0 fixed, node i+1 is DOF i,
    springs as zeroLength elements, loads as patterns."""
    ops.wipe()
    ops.model("basic", "-ndm", 1, "-ndf", 1)
    n = problem["n_dof"]
    ops.node(0, 0.0)
    ops.fix(0, 1)
    for i in range(n):
        ops.node(i + 1, 0.0)
        ops.mass(i + 1, problem["mass"][i][i])
    for i, k in enumerate(problem["springs"]):
        if k is None:
            spring = problem["nonlinear_spring"]
            ops.uniaxialMaterial("ElasticMultiLinear", i + 1, 0.0, "-strain",
                                 *spring["strain"], "-stress", *spring["force"])
        else:
            ops.uniaxialMaterial("Elastic", i + 1, k)
        ops.element("zeroLength", i + 1, i, i + 1, "-mat", i + 1, "-dir", 1,
                    "-doRayleigh", 1)
    ops.rayleigh(*problem["rayleigh"], 0.0, 0.0)
    add_load(problem)


def add_load(problem):
    """The load pattern: a Trig series on one node, or a ground motion."""
    load = problem["load"]
    if load["kind"] == "sine":
        ops.timeSeries("Trig", 1, 0.0, 1.0e6, load["period"],
                       "-factor", load["amplitude"])
        ops.pattern("Plain", 1, 1)
        ops.load(load["dof"] + 1, 1.0)
    else:
        ops.timeSeries("Path", 1, "-dt", load["dt"], "-values", *load["values"],
                       "-useLast")
        ops.pattern("UniformExcitation", 1, 1, "-accel", 1)


def set_initial_state(problem):
    """y_0, y'_0 and a_0 committed at the nodes."""
    a0 = initial_acceleration(problem)
    for i in range(problem["n_dof"]):
        ops.setNodeDisp(i + 1, 1, problem["y0"][i], "-commit")
        ops.setNodeVel(i + 1, 1, problem["yp0"][i], "-commit")
        ops.setNodeAccel(i + 1, 1, float(a0[i]), "-commit")
    ops.setTime(problem["t0"])


def opensees_run(problem, command, linear_algorithm=False):
    """OpenSees's trajectory under the integrator ``command``: t, y, y', y''."""
    build_model(problem)
    set_initial_state(problem)
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.test("NormDispIncr", TOLERANCE, MAX_ITERATIONS)
    ops.algorithm("Linear" if linear_algorithm else "Newton")
    ops.integrator(*command)
    ops.analysis("Transient")
    nodes = range(1, problem["n_dof"] + 1)

    def state():
        return (ops.getTime(), [ops.nodeDisp(i, 1) for i in nodes],
                [ops.nodeVel(i, 1) for i in nodes],
                [ops.nodeAccel(i, 1) for i in nodes])
    out = [state()]
    for _ in range(problem["n_steps"]):
        if ops.analyze(1, problem["h"]) != 0:
            raise RuntimeError(f"OpenSees failed with {command}")
        out.append(state())
    ops.wipe()
    return [np.array(column) for column in zip(*out)]


def distance(ours, theirs):
    """max |theirs - ours| / max |ours| over steps and DOFs (y, y', y'')."""
    return [float(np.max(np.abs(b - a)) / np.max(np.abs(a)))
            for a, b in zip(ours[1:], theirs[1:])]


def command_text(command):
    """The openseespy call, as text."""
    return f"integrator({', '.join(repr(c) for c in command)})"


NOTES = [
    "y, yp, ypp: one list per step (y0, then 200 steps), one value per DOF",
    "t: OpenSees's own time, accumulated step by step (HHT and "
    "generalized-alpha add (1 - alpha_f) h, then alpha_f h), so it drifts "
    "from t0 + n h by rounding",
    "ypp[0] = M^-1 (f(t0) - C yp0 - R(y0)), given to OpenSees with setNodeAccel",
    "agreement_with_formula: max over steps and DOFs of |OpenSees y - "
    "formula y| / max |formula y|, the formula's load taken at "
    "t0 + (n + 1 - alpha_f) h; agreement_yp, agreement_ypp: the same for "
    "y' and y''; agreement_at_opensees_times: the largest of the three with "
    "the load at OpenSees's t_n + (1 - alpha_f) h",
]


def member_record(problem, params):
    """One member's trajectory and its agreements with the formula."""
    t, y, yp, ypp = ours = opensees_run(problem, params["command"])
    exact = distance(formula_run(problem, params), ours)
    at_times = max(distance(formula_run(problem, params, t), ours))
    return {
        **{k: params[k] for k in ("alpha_m", "alpha_f", "beta", "gamma")},
        "opensees_command": command_text(params["command"]),
        "agreement_with_formula": exact[0], "agreement_yp": exact[1],
        "agreement_ypp": exact[2], "agreement_at_opensees_times": at_times,
        "t": t.tolist(), "y": y.tolist(), "yp": yp.tolist(),
        "ypp": ypp.tolist()}


def case_record(name, problem):
    """The JSON content of one case."""
    members = {label: member_record(problem, params)
               for label, params in MEMBERS.items()}
    problem = dict(problem)
    return {"opensees_version": ops.version(), "case": name,
            "description": problem.pop("description"), "notes": NOTES,
            "problem": problem, "members": members}


def dumps(value, indent=0):
    """JSON with a fixed layout: objects one key a line, a list of numbers
    on one line, a list of lists or strings one item a line."""
    pad, inner = " " * indent, " " * (indent + 1)
    if isinstance(value, dict):
        items = [f"{inner}{json.dumps(k)}: {dumps(v, indent + 1)}"
                 for k, v in value.items()]
        return "{\n" + ",\n".join(items) + "\n" + pad + "}"
    if isinstance(value, list) and value and isinstance(value[0], (list, str)):
        return ("[\n" + ",\n".join(inner + json.dumps(v, separators=(",", ":"))
                                   for v in value) + "\n" + pad + "]")
    return json.dumps(value, separators=(",", ":"))


def zero_start_chain():
    """The damped chain with a_g(0) = 0, so that y_0 = y'_0 = a_0 = 0."""
    problem = chain_case()
    problem["load"] = {**problem["load"], "values": [0.0] + problem["load"]["values"][1:]}
    return problem


def checks():
    """The two OpenSees integrators left out, against the formula: rows of
    (what, case, agreement in y, y', y'')."""
    ga, cd = MEMBERS["generalized-alpha"], MEMBERS["central difference"]
    ga_command = ("GeneralizedAlpha", 1 - ga["alpha_m"], 1 - ga["alpha_f"])
    rows = []
    for name, problem in [(n, build()) for n, build in CASES.items()] + [
            ("chain, a_g(0) = 0", zero_start_chain())]:
        theirs = opensees_run(problem, ga_command)
        rows.append(("GeneralizedAlpha vs generalized-alpha", name,
                     distance(formula_run(problem, ga), theirs)))
        rows.append(("GeneralizedAlpha vs the same, alpha_m = 0", name,
                     distance(formula_run(problem, {**ga, "alpha_m": 0.0}), theirs)))
        if problem["nonlinear_spring"] is None:
            theirs = opensees_run(problem, ("CentralDifference",), True)
            rows.append(("CentralDifference vs central difference", name,
                         distance(formula_run(problem, cd), theirs)))
    return command_text(ga_command), rows


def print_table(records, key, title):
    """One agreement of every member (rows) and case (columns)."""
    print(title)
    print(f"{'':22s}" + "".join(f"{c:>18s}" for c in records))
    for label in MEMBERS:
        print(f"{label:22s}" + "".join(
            f"{r['members'][label][key]:18.1e}" for r in records.values()))


def main():
    OUT.mkdir(parents=True, exist_ok=True)
    records = {name: case_record(name, build()) for name, build in CASES.items()}
    for name, record in records.items():
        (OUT / f"{name}.json").write_text(dumps(record) + "\n")
    print(f"OpenSees {ops.version()}, max |OpenSees - formula| / max |formula|")
    print_table(records, "agreement_with_formula",
                "y, load at t0 + (n + 1 - alpha_f) h:")
    print_table(records, "agreement_at_opensees_times",
                "y, y', y'', load at OpenSees's t_n + (1 - alpha_f) h:")
    command, rows = checks()
    print(f"\nleft out, y; y'; y'' (GeneralizedAlpha: {command}):")
    for what, name, d in rows:
        print(f"  {what:42s} {name:18s} {d[0]:8.1e} {d[1]:8.1e} {d[2]:8.1e}")

if __name__ == "__main__":
    main()
