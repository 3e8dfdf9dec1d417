"""Independent reference for steady 2D rolling with any pressure, including several contact zones.

Written without reference to ``rail/``: only the continuous problem is shared (report secs 4.3, 5).
In steady rolling the traction does not change in the frame of the contact, du/dt = 0, so the slip
velocity is local, s(x) = V (gamma - u'(x)), and a particle that re-enters contact after a gap sticks
if and only if u' = gamma can hold there: no history is needed (this is what makes the steady state a
check of the unsteady march, whose particles carry their displacement through the gaps).

Discretisation: piecewise-constant traction on elements of length h centred at x_i (the pressure
given there); the displacement u(x) = -k int q(z) ln|x - z| dz at the centres (exact element integrals),
k = 4 (1 - nu^2) / (pi E); u' between neighbouring centres by the difference (u_{i+1} - u_i) / h (the
particle at x_i came from x_{i+1}: the element ahead, loaded or not). Stick elements: u' = gamma;
slip elements: q = -mu p sign(s) with s / V = gamma - u'; an active-set iteration (|q| > mu p ->
slip, slip against its traction -> stick). Elements with p = 0 carry no traction. First order in h at
the square-root edges.
"""

import numpy as np


def steady_rolling(x, p, gamma, mu, k, max_iter=500):
    """Steady 2D rolling traction on a uniform grid.

    Parameters
    ----------
    x : (n,) element centres [m], uniformly spaced
    p : (n,) pressure [Pa], >= 0 (0 in gaps)
    gamma : creepage [-]; mu : friction coefficient [-]; k : compliance 4 (1 - nu^2) / (pi E) [1/Pa]

    Returns
    -------
    q : (n,) traction [Pa]; slip : (n,) s / V = gamma - u' [-] (0 in stick, 0 where p = 0);
    stick : (n,) bool
    """
    x = np.asarray(x, dtype=float)
    p = np.asarray(p, dtype=float)
    h = x[1] - x[0]

    def g(t):  # int ln|t| dt
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(t == 0, 0.0, t * np.log(np.abs(t)) - t)

    xe = np.append(x, x[-1] + h)  # the centres and one beyond the last (the particle ahead of it)
    d = xe[:, None] - x[None, :]
    U = -k * (g(d + h / 2) - g(d - h / 2))  # u at xe from unit q on element j
    D = (U[1:] - U[:-1]) / h  # u'_i = sum_j D_ij q_j, between x_i and x_{i+1}
    loaded = p > 0
    stick = loaded.copy()
    sign = np.full(x.size, -np.sign(gamma) if gamma != 0 else 1.0)
    for _ in range(max_iter):
        slip = loaded & ~stick
        q = np.where(slip, mu * p * sign, 0.0)
        S = np.flatnonzero(stick)
        if S.size:
            q[S] = np.linalg.solve(D[np.ix_(S, S)], gamma - D[S][:, slip] @ q[slip])
        s = np.where(loaded, gamma - D @ q, 0.0)
        over = stick & (np.abs(q) > mu * p)
        wrong = slip & (s * sign > 0)  # q = -mu p sign(s) violated
        if not (over.any() or wrong.any()):
            s[stick] = 0.0
            return q, s, stick
        sign[over] = np.sign(q[over])
        stick[over] = False
        stick[wrong] = True
    raise RuntimeError("the steady stick/slip iteration did not settle")
