"""Euler's torque-free rigid body in the report's second-order form (eqs. 15-18).

Differentiating Euler's equations I1 w1' = (I2 - I3) w2 w3 (and cyclic)
once gives w_i'' = alpha_i(w) w_i with the alpha_i of eqs. 16-18; the
report adds a term beta w_i' that it never defines.  The torque-free body
needs beta = 0, the default here.

The second-order form needs w'(0) as well.  The report prints w'(0) = 0,
which Euler's equations contradict: with I = (3, 2, 1) and
w(0) = (1, 0.01, 0.01) they give w'(0) = (1e-4 / 3, -0.01, 0.01).  Both are
provided: ``initial_rates="consistent"`` follows the rigid body and has an
exact solution in Jacobi elliptic functions; ``initial_rates="printed"``
solves the second-order equations as printed, a different motion that does
not conserve the energy of eq. 19, whose reference is a tight scipy solve.
"""

import numpy as np
from numba import njit

from ._problem import Problem

MOMENTS = (3.0, 2.0, 1.0)
INITIAL_RATE = (1.0, 0.01, 0.01)
T_SPAN = (0.0, 80.0)
STEP = 0.016


@njit(cache=True)
def rigid_body_rhs(t, w, wp, i1, i2, i3, beta):
    """w'' = alpha(w) w - beta w' with alpha_i from eqs. 16-18, as a tuple
    (no array allocated per evaluation)."""
    a1 = (w[2] ** 2 * (i2 - i3) * (i3 - i1) / (i1 * i2)
          + w[1] ** 2 * (i2 - i3) * (i1 - i2) / (i1 * i3))
    a2 = (w[0] ** 2 * (i3 - i1) * (i1 - i2) / (i2 * i3)
          + w[2] ** 2 * (i2 - i3) * (i3 - i1) / (i2 * i1))
    a3 = (w[1] ** 2 * (i1 - i2) * (i2 - i3) / (i3 * i1)
          + w[0] ** 2 * (i1 - i2) * (i3 - i1) / (i3 * i2))
    return (a1 * w[0] - beta * wp[0], a2 * w[1] - beta * wp[1], a3 * w[2] - beta * wp[2])


def euler_rates(w, moments=MOMENTS):
    """w' from Euler's first-order equations, for w of shape (3, ...)."""
    i1, i2, i3 = moments
    return np.array([(i2 - i3) / i1 * w[1] * w[2],
                     (i3 - i1) / i2 * w[2] * w[0],
                     (i1 - i2) / i3 * w[0] * w[1]])


def energy(moments=MOMENTS):
    """E = 1/2 sum I_i w_i^2 (eq. 19), for w of shape (3, k)."""
    inertia = np.asarray(moments, dtype=float)[:, None]
    return lambda w, wp: 0.5 * np.sum(inertia * w * w, axis=0)


def angular_momentum_squared(moments=MOMENTS):
    """|L|^2 = sum I_i^2 w_i^2, conserved by the torque-free body."""
    inertia = np.asarray(moments, dtype=float)[:, None]
    return lambda w, wp: np.sum((inertia * w) ** 2, axis=0)


def euler_top_exact(t, w0, moments=MOMENTS):
    """Exact torque-free motion w(t) through Jacobi elliptic functions.

    With principal moments A > B > C (any order of axes), energy E and
    |L|^2 = L2: for L2 > 2 E B the body tumbles about the A axis and

        w_A = sA sqrt((L2 - 2EC) / (A (A - C))) dn(u, m),
        w_B = sB sqrt((2EA - L2) / (B (A - B))) sn(u, m),
        w_C =    sqrt((2EA - L2) / (C (A - C))) cn(u, m),
        u = lam t + u0,  lam^2 = (A - B)(L2 - 2EC) / (A B C),
        m = (B - C)(2EA - L2) / ((A - B)(L2 - 2EC));

    for L2 < 2 E B the roles of A and C are exchanged.  The phase u0 and the
    signs come from w0 and Euler's equations (Landau & Lifshitz,
    "Mechanics", Sec. 37).

    Returns
    -------
    w, wp : ndarray, shape (3, k)
        The angular velocity and its derivative (from Euler's equations).
    """
    t = np.atleast_1d(np.asarray(t, dtype=float))
    inertia = np.asarray(moments, dtype=float)
    w0 = np.asarray(w0, dtype=float)
    if len(set(inertia)) != 3:
        raise ValueError("moments must be distinct")
    two_e = np.sum(inertia * w0 ** 2)
    l2 = np.sum((inertia * w0) ** 2)
    a, b, c = np.argsort(inertia)[::-1]  # axes of the largest, middle, smallest moment
    if l2 < two_e * inertia[b]:
        a, c = c, a
    A, B, C = inertia[[a, b, c]]
    if w0[a] == 0 or l2 == two_e * B:
        raise ValueError("separatrix or degenerate motion: not covered")
    amp_a = np.sqrt((l2 - two_e * C) / (A * (A - C)))
    amp_b = np.sqrt((two_e * A - l2) / (B * (A - B)))
    amp_c = np.sqrt((two_e * A - l2) / (C * (A - C)))
    lam = np.sqrt((A - B) * (l2 - two_e * C) / (A * B * C))
    m = (B - C) * (two_e * A - l2) / ((A - B) * (l2 - two_e * C))
    # Euler: I_b w_b' = parity (I_c - I_a) w_c w_a; the sign of sn follows.
    parity = np.linalg.det(np.eye(3)[[a, b, c]])
    s_a = np.sign(w0[a])
    s_b = np.sign(parity * (C - A) * s_a)
    phi0 = np.arctan2(w0[b] / (s_b * amp_b), w0[c] / amp_c)
    from scipy.special import ellipj, ellipkinc   # here: scipy takes 0.3 s to import
    u0 = ellipkinc(phi0, m)
    sn, cn, dn, _ = ellipj(lam * t + u0, m)
    w = np.empty((3, t.size))
    w[a] = s_a * amp_a * dn
    w[b] = s_b * amp_b * sn
    w[c] = amp_c * cn
    return w, euler_rates(w, moments)


def rigid_body(initial_rates="consistent", beta=0.0):
    """Euler's rigid body in second-order form (report Sec. 3.2).

    I = (3, 2, 1), w(0) = (1, 0.01, 0.01), t in [0, 80], h = 0.016.

    Parameters
    ----------
    initial_rates : {"consistent", "printed"}
        "consistent": w'(0) from Euler's equations, (1e-4/3, -0.01, 0.01);
        exact solution in Jacobi elliptic functions.  "printed": the
        report's w'(0) = 0; reference is a DOP853 solve at rtol 1e-13.
    beta : float
        The report's undefined damping coefficient of eq. 15 (0 for the
        torque-free body; the exact solution needs beta = 0).
    """
    if initial_rates not in ("consistent", "printed"):
        raise ValueError(
            f"initial_rates must be 'consistent' or 'printed', got {initial_rates!r}")
    w0 = np.array(INITIAL_RATE)
    consistent = initial_rates == "consistent"
    wp0 = euler_rates(w0) if consistent else np.zeros(3)
    exact = (lambda t: euler_top_exact(t, w0)) if consistent and beta == 0 else None
    return Problem(
        name=f"rigid body ({initial_rates} initial rates)",
        fun=rigid_body_rhs, args=MOMENTS + (float(beta),),
        y0=w0, yp0=wp0, t_span=T_SPAN, h=STEP, exact=exact,
        invariants={"energy": energy(), "|L|^2": angular_momentum_squared()},
        notes=("w'(0) from Euler's equations" if consistent else
               "w'(0) = 0 as printed: not a motion of the rigid body"),
    )
