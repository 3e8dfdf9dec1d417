"""The rail head's longitudinal displacement at the moving contact on a track cell of N bays whose supports
differ (rail.cell): the head's operator of rail.creepage.rail_flexibility (the axial rod on the pads' shear springs and
the head's e psi from the bending rotation) with the cell's supports and dampers (issue 55).

What is modelled
----------------
* **The axial rod** (E A, rho A, the rail's damping) on one longitudinal spring per *support* of the
  cell, at the support's position: support j's pad sheared, k_x,j = k_x f_j (1 + i eta_x sign(omega))
  or k_x f_j + i omega c_x f_j, f_j = k_P,j / k_P the support's pad factor (its vertical stiffness over
  the nominal pad's: a pad stiffer or softer through its elastomer's modulus or thickness is so in
  shear as in compression, k_P and k_x both scale as G A / t). The sleeper is held longitudinally, as
  on the uniform track (rail.creepage.rail_flexibility): its ballast, sleeper mass and a void under it (a vertical
  gap; the crib ballast still holds the sleeper along the rail) do not enter the rod.
* **The rail dampers act vertically only.** A tuned rail damper (masses in an elastomer clipped to
  the web and foot) is designed and characterised for the rail's vertical and lateral vibration
  (Thompson, Jones, Waters & Farrington, Applied Acoustics 68 (2007) 43-57; modelled vertically by
  Croft, Jones & Thompson, J. Sound Vib. 323 (2009)); no longitudinal tuning or stiffness is
  published, so the damper adds no spring to the rod. It acts on the head through the bending: its
  vertical force K_D w (rail.cell.point_stiffness) is in the cell's Timoshenko solution whose rotation
  psi moves the head by e psi. Its force acts through the section (web): no moment on the rail.
* **The head's e psi**: the Timoshenko rail (w, psi) on the cell's vertical attachments (supports and
  dampers, rail.cell.point_stiffness), the longitudinal force on the running surface at the height e an
  axial force and a moment e F_x, u_head = u_n + e psi, as rail.creepage.rail_flexibility.

Left out as on the uniform track: the pads' rotational stiffness and the coupling of the rod to the
bending through the pads; the longitudinal friction of the clips.

The moving-load matrices
------------------------
A load l exp(i Omega t) at x = V t on the rail periodic over the cell (length P, attachments at s_q,
beta_P = 2 pi / P), the response r at the load, the supported variable s (w for the beam, u_n for
the rod): with h^x_j = H_x(beta - j beta_P, omega), omega = Omega + beta V, e_qj = exp(i (beta - j beta_P) s_q)
(rail.moving's cell table with the transfers of rail.creepage.rail_flexibility)::

    A[p, k] = delta_pk / 2pi int h^rl_k db - 1 / (2 pi P) int sum_q h^rs_p e_qp Y_qk db,
    Y_k = (I + diag(K) S / P)^-1 diag(K) (h^sl_k / e_k),   S[l, j] = sum_m H_ss(beta + m beta_P) e^{i (beta + m beta_P)(s_j - s_l)}.

S in closed form per distance (rail.cell.cell_lattice_sum; the rod's poles for the rod). With
Omega = 0 the columns k are the loads at k Omega_P, Omega_P = 2 pi V / P, abs(k) <= J: one table over the
cell's harmonics (J = N K reaches K Omega_0 as the uniform track's classes do); for N identical supports at
equal spacing its entries with p = k (mod N) are the uniform track's Bloch tables (rail.creepage.rail_flexibility.head_table,
nu = (k mod N) / N) and the others vanish. Column 0 diverges at the static point (beta -> 0): within half a
cell wavenumber of it the divergent lattice term H_ss(beta) is taken out of S and put back by the
Sherman-Morrison formula (as rail.moving), so that no entry is formed from the difference of two large
ones: with B = I + diag(K) S' / P, a = exp(-i beta s), b = 1 / a, z = B^-1 diag(K) a, c = b . z and
h = H_ss(beta), g = H_sl(beta), the static column's reactions are g z / (1 + h c / P), its row
h^rs t_k / (1 + h c / P) (t_k = b . B^-1 diag(K) (h^sl_k / e_k)) and its diagonal
(H_rl P + c X) / (P + h c), X = H_rl h - H_rs g in closed form (0, or 1 / det D for psi per moment).

References
----------
Sheng, Thompson & Jones, report sec. 4.3 (eq 26); docs/track.md ("A cell of N bays"); rail.creepage.rail_flexibility.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from ..cell import TrackCell, cell_lattice_sum, cell_sum_matrix, point_stiffness
from .rail_flexibility import DEFAULT_HEAD_HEIGHT, DEFAULT_LONGITUDINAL_STIFFNESS, HeadOperator, HeadTable, RailHead, free_beam_matrix, rod_receptance
from ..quadrature import adaptive_panels
from ..track import Track, damped_stiffness, lattice_tails

__all__ = ["CellHead", "cell_head_matrix", "cell_head_table", "cell_head_operator", "rod_poles", "rod_point_stiffness", "table_seconds",
           "cell_memory_mb"]


@dataclass(frozen=True)
class CellHead:
    """The rail head's longitudinal flexibility on a track cell (module docstring), SI units.

    Attributes
    ----------
    cell : rail.cell.TrackCell (rail, supports, dampers, damping model)
    longitudinal_stiffness : k_x, the nominal pad's longitudinal (shear) stiffness [N/m] (support j: k_x f_j)
    longitudinal_loss_factor : eta_x [-], >= 0 (hysteretic model)
    longitudinal_viscous_damping : c_x [N s/m], >= 0 (viscous model; support j: c_x f_j)
    head_height : e, the running surface above the neutral axis [m], in [0, 0.3]
    bending : whether the head's motion from the bending rotation is included (False: the rod alone)
    """

    cell: TrackCell
    longitudinal_stiffness: float = DEFAULT_LONGITUDINAL_STIFFNESS
    longitudinal_loss_factor: float = 0.25
    longitudinal_viscous_damping: float = 0.0
    head_height: float = DEFAULT_HEAD_HEIGHT
    bending: bool = True

    def __post_init__(self):
        if not isinstance(self.cell, TrackCell):
            raise TypeError(f"CellHead.cell must be a rail.cell.TrackCell, not {type(self.cell).__name__}.")
        _ = self.nominal  # the uniform head's checks of every parameter (keys, values and ranges named)

    @property
    def nominal(self) -> RailHead:
        """The uniform track's head with the cell's nominal support (rail.creepage.rail_flexibility.RailHead)."""
        return RailHead(self.cell.track, self.longitudinal_stiffness, self.longitudinal_loss_factor, self.longitudinal_viscous_damping,
                        self.head_height, self.bending)

    @property
    def track(self) -> Track:
        """The cell's nominal track (spacing: the mean P / N)."""
        return self.cell.track

    @property
    def pad_factors(self) -> np.ndarray:
        """f_j = k_P,j / k_P per support [-]: the factor on the nominal k_x and c_x (module docstring)."""
        k0 = self.cell.track.pad.stiffness
        return np.array([s.pad.stiffness / k0 for s in self.cell.supports], dtype=float)

    @property
    def label(self) -> str:
        """What the model holds, for results and messages."""
        c = self.cell
        part = "rod on the pads' shear springs" + (f" and the head's bending rotation (e = {self.head_height * 1e3:.1f} mm)"
                                                   if self.bending else "")
        dampers = f"; its {len(c.dampers)} rail dampers act vertically only" if c.dampers else ""
        return (f"rail's longitudinal flexibility ({part}, k_x = {self.longitudinal_stiffness:.3g} N/m per nominal support "
                f"times each pad's factor, on the track cell of {c.bays} bays{dampers})")


def _axial_stiffness(track: Track, omega):
    """E A (1 + i eta_R sign(omega)) or E A (1 + i omega tau_R) [N] (rail.creepage.rail_flexibility's rod)."""
    r = track.rail
    f = 1 + 1j * r.loss_factor * np.sign(omega) if track.damping == "hysteretic" else 1 + 1j * omega * r.damping_time
    return r.youngs_modulus * r.area * f


def rod_poles(omega, track):
    """The axial rod's free receptance H_u = c / (beta^2 - p^2) as partial fractions: c = 1 / EA, p^2 = rho A omega^2 / EA.

    Parameters
    ----------
    omega : ndarray
        Angular frequency [rad/s], != 0.
    track : rail.track.Track

    Returns
    -------
    (c, p) : complex ndarrays of shape (1,) + omega.shape
        c [1/N], p [rad/m] with Im p >= 0 (rail.cell.cell_lattice_sum's ``poles``).
    """
    w = np.asarray(omega, dtype=float)
    EA = _axial_stiffness(track, w)
    p = np.sqrt(track.rail.density * track.rail.area * w**2 / EA + 0j)
    p = np.where(p.imag < 0, -p, p)
    return (1.0 / EA)[None], p[None]


def rod_point_stiffness(head: CellHead, omega) -> np.ndarray:
    """The longitudinal springs of the cell's supports, k_x f_j (1 + i eta_x sign(omega)) or (k_x + i omega c_x) f_j.

    Parameters
    ----------
    head : CellHead
    omega : float or ndarray
        Angular frequency [rad/s].

    Returns
    -------
    complex ndarray, shape omega.shape + (supports,)
        [N/m] (the cell's damping model).
    """
    w = np.asarray(omega, dtype=float)
    k = damped_stiffness(head.longitudinal_stiffness, head.longitudinal_loss_factor, head.longitudinal_viscous_damping, w,
                         head.cell.track.damping)
    return np.asarray(k)[..., None] * head.pad_factors


def _rod_positions(cell: TrackCell) -> np.ndarray:
    return np.array([s.position for s in cell.supports], dtype=float)


def _rod_sum_matrix(beta, omega, s, P, track, exclude_zero=False, explicit=40, tail=4000):
    """S[l, j] = sum_m H_u(beta + m beta_P) exp(i (beta + m beta_P) (s_j - s_l)) (without m = 0 with ``exclude_zero``:
    H_u itself to abs(m) = explicit, its quasi-static 1 / (EA q^2) beyond: to ``tail`` explicitly off the diagonal,
    in closed form by polygamma on it, as rail.cell.cell_lattice_sums_excluding does for the beam)."""
    d = np.round(s[None, :] - s[:, None], 12)
    xs, inv = np.unique(d, return_inverse=True)
    inv = inv.reshape(d.shape)
    if not exclude_zero:
        poles = rod_poles(omega, track)
        vals = np.stack([cell_lattice_sum(beta, omega, float(x), P, track, poles=poles) for x in xs], axis=-1)
        return vals[:, inv]
    bP = 2 * np.pi / P
    m1 = np.concatenate([np.arange(-explicit, 0), np.arange(1, explicit + 1)])
    q1 = beta[:, None] + m1[None, :] * bP
    vals = rod_receptance(q1, omega[:, None], track) @ np.exp(1j * np.outer(m1 * bP, xs))
    EA = _axial_stiffness(track, omega)
    zero = xs == 0
    if (~zero).any():
        m2 = np.concatenate([np.arange(-tail, -explicit), np.arange(explicit + 1, tail + 1)])
        q2 = beta[:, None] + m2[None, :] * bP
        vals[:, ~zero] += (1.0 / (EA[:, None] * q2**2)) @ np.exp(1j * np.outer(m2 * bP, xs[~zero]))
    vals *= np.exp(1j * np.outer(beta, xs))
    if zero.any():
        s2 = lattice_tails(beta, bP, explicit)[1]
        vals[:, zero] += (s2 / EA)[:, None]
    return vals[:, inv]


def _attached(beta, js, s, P, bP, Kq, S, Sx, near, col, cols, rows, kinds):
    """The reactions and diagonals of the module docstring at the nodes ``beta`` for the column types ``cols``
    ({l: h^sl (n, J)}), the row types ``rows`` ({r: h^rs (n, J)}) and ``kinds`` ([(name, r, l, h^rl (n, J), X (n,))]).

    S: the lattice sums at the nodes not ``near`` (n_far, Q, Q); Sx: without the m = 0 term at the ``near`` ones;
    col: the static column's index (None: no static point). Returns ({l: Y (n, Q, J)}, {name: diag (n, J)},
    {name: row (n, J) or None}, {r: U (n, Q, J)}) with U's static column zero at the near nodes (its part is the row)."""
    n, J, Q = len(beta), len(js), len(s)
    eplus = np.exp(1j * beta[:, None] * s[None, :])[:, :, None] * np.exp(-1j * bP * np.outer(s, js))[None]
    U = {r: Hr[:, None, :] * eplus for r, Hr in rows.items()}
    Vv = {l_: Hc[:, None, :] / eplus for l_, Hc in cols.items()}
    far = ~near
    eye = np.eye(Q)
    Y = {l_: np.empty((n, Q, J), dtype=complex) for l_ in cols}
    if far.any():
        Mx = eye[None] + Kq[far][:, :, None] * S / P
        for l_ in cols:
            Y[l_][far] = np.linalg.solve(Mx, Kq[far][:, :, None] * Vv[l_][far])
    diag = {}
    rowd = {}
    if near.any():
        bn = beta[near]
        Kn = Kq[near]
        B = eye[None] + Kn[:, :, None] * Sx / P
        a = np.exp(-1j * bn[:, None] * s[None, :])
        b = 1.0 / a
        z = np.linalg.solve(B, (Kn * a)[:, :, None])[:, :, 0]
        c = np.sum(b * z, axis=1)
        self_type = next(iter(cols))  # the supported variable's own column (h = H_ss): 'u' for the rod, 'F' for the beam
        h = cols[self_type][near, col]
        den = 1.0 + h * c / P
        gam = h / (P + h * c)
        t = {}
        for l_ in cols:
            Z = np.linalg.solve(B, Kn[:, :, None] * Vv[l_][near])
            t[l_] = np.einsum("nq,nqj->nj", b, Z)
            Yn = Z - z[:, :, None] * (gam[:, None] * t[l_])[:, None, :]
            Yn[:, :, col] = (cols[l_][near, col] / den)[:, None] * z
            Y[l_][near] = Yn
    for name, r, l_, Hrl, X in kinds:
        d = Hrl - np.einsum("nqj,nqj->nj", U[r], Y[l_]) / P
        rw = None
        if near.any():
            hr = rows[r][near, col]
            d[near, col] = (Hrl[near, col] * P + c * X[near]) / (P + h * c)
            rw = np.zeros((n, J), dtype=complex)
            rw[near] = (hr / den)[:, None] * t[l_]
            rw[near, col] = 0.0
        diag[name] = d
        rowd[name] = rw
    if near.any():
        for r in U:
            U[r][near, :, col] = 0.0
    return Y, diag, rowd, U


def _rod_nodes(beta, Omega, V, js, head: CellHead, static, near_all):
    cell, tr = head.cell, head.cell.track
    P, bP = cell.period, cell.beta_p
    s = _rod_positions(cell)
    om = Omega + beta * V
    Hu = rod_receptance(beta[:, None] - js[None, :] * bP, om[:, None], tr)
    Kq = rod_point_stiffness(head, om)
    near = near_all if static is not None else np.zeros(len(beta), dtype=bool)
    S = _rod_sum_matrix(beta[~near], om[~near], s, P, tr) if (~near).any() else None
    Sx = _rod_sum_matrix(beta[near], om[near], s, P, tr, exclude_zero=True) if near.any() else None
    zero = np.zeros(len(beta), dtype=complex)
    return _attached(beta, js, s, P, bP, Kq, S, Sx, near, static, {"u": Hu}, {"u": Hu}, [("rod", "u", "u", Hu, zero)])


def _beam_nodes(beta, Omega, V, js, head: CellHead, static, near_all, kinds):
    cell = head.cell
    P, bP = cell.period, cell.beta_p
    s = cell.positions
    om = Omega + beta * V
    b = beta[:, None] - js[None, :] * bP
    Hww, HwM, HpF, HpM, inv = free_beam_matrix(b, om[:, None], cell.track)
    Kq = point_stiffness(cell, om)
    near = near_all if static is not None else np.zeros(len(beta), dtype=bool)
    S = cell_sum_matrix(beta[~near], om[~near], cell) if (~near).any() else None
    Sx = cell_sum_matrix(beta[near], om[near], cell, exclude_zero=True) if near.any() else None
    dx = -1j * b  # d/dx of a response at beta - j beta_P (W = int w exp(+i beta x) dx)
    zero = np.zeros(len(beta), dtype=complex)
    Xinv = inv[:, static] if static is not None else zero
    table = {"psiF": ("psi", "F", HpF, zero), "psiM": ("psi", "M", HpM, Xinv), "dpsiF": ("dpsi", "F", dx * HpF, zero),
             "wM": ("w", "M", HwM, zero)}
    ks = [(k,) + table[k] for k in kinds]
    rows = {r: {"psi": HpF, "dpsi": dx * HpF, "w": Hww}[r] for r in dict.fromkeys(t[1] for t in ks)}
    return _attached(beta, js, s, P, bP, Kq, S, Sx, near, static, {"F": Hww, "M": HwM}, rows, ks)


def cell_head_matrix(head: CellHead, speed: float, Omega: float, js, kinds=("rod", "psiM", "psiF"), rtol: float = 1e-4,
                     order: int = 16, max_panels: int = 40000, block: int | None = None):
    """The moving-load matrices A[p, k] = a_{p-k}(Omega + k Omega_P) on the cell (module docstring), at the contact,
    for the rows and columns ``js`` (integers, contiguous, harmonics of Omega_P = 2 pi V / P).

    Parameters
    ----------
    head : CellHead
    speed : float
        V [m/s], > 0.
    Omega : float
        Base frequency [rad/s]: column k is the load at Omega + k Omega_P (a nonzero whole multiple of Omega_P
        only if the static column -Omega / Omega_P lies outside js).
    js : sequence of int
        The harmonic indices of the rows and columns.
    kinds : tuple of str
        'rod' (u_n per longitudinal force on the neutral axis), 'psiM' (psi per moment), 'psiF' (psi per
        downward force), 'dpsiF' (d psi / dx at the contact per downward force), 'wM' (w per moment).
    rtol : float
        Relative tolerance of the adaptive wavenumber rule [-].
    order, max_panels : int
        The rule's Gauss order per half panel and its most panels [-].
    block : int, optional
        Nodes per block of the node tables [-] (default about 2**21 / (attachments x columns)).

    Returns
    -------
    dict of str to complex ndarray (J, J)
        [m/N], [rad/(N m)], [rad/N], [rad/(m N)], [m/(N m)]; and 'nodes': the quadrature nodes used (rod, beam).
    """
    if not (np.isfinite(speed) and speed > 0):
        raise ValueError(f"speed = {speed!r} m/s is not allowed: it must be a finite number > 0.")
    if not np.isfinite(Omega):
        raise ValueError(f"Omega = {Omega!r} rad/s is not allowed: it must be finite.")
    js = np.asarray(js, dtype=int)
    cell = head.cell
    bP, V = cell.beta_p, float(speed)
    kk = Omega / (bP * V)
    static = None
    if abs(kk - round(kk)) < 1e-12 and -int(round(kk)) in js:  # the column whose h diverges at omega = 0
        if round(kk) != 0:
            raise ValueError("cell_head_matrix: Omega a nonzero whole multiple of Omega_P puts the static point in another "
                             "column; pass Omega in [0, Omega_P) and shift js.")
        static = int(np.where(js == 0)[0][0])
    J = len(js)
    Bmap = (np.max(np.abs(js)) + 4) * bP
    beta_s = -Omega / V
    jm = int(np.max(np.abs(js)))
    th_edges = np.unique(np.concatenate([np.linspace(-np.pi / 2, np.pi / 2, 97), [np.arctan(beta_s / Bmap)],
                                         np.arctan((np.arange(-jm - 2, jm + 3) + 0.5) * bP / Bmap)]))
    c0 = int(np.argmin(np.abs(js)))
    Qb = len(cell.positions)
    if block is None:
        block = int(min(4096, max(64, 2**21 // (Qb * J))))

    def to_beta(th):
        return Bmap * np.tan(th), Bmap / np.cos(th) ** 2

    def nodes(g, beta):
        near = np.abs(beta) < bP / 2
        if g == "rod":
            return _rod_nodes(beta, Omega, V, js, head, static, near)
        return _beam_nodes(beta, Omega, V, js, head, static, near, beam_kinds)

    beam_kinds = tuple(k for k in kinds if k != "rod")
    groups = (["rod"] if "rod" in kinds else []) + (["beam"] if beam_kinds else [])
    out = {"nodes": []}
    for g in groups:
        names = ["rod"] if g == "rod" else list(beam_kinds)
        first = "u" if g == "rod" else "F"

        def proxy(th, g=g, names=names, first=first):
            res = []
            for lo in range(0, len(th), block):
                beta, jac = to_beta(th[lo:lo + block])
                Y, diag, _, _ = nodes(g, beta)
                res.append(np.concatenate([diag[k] for k in names] + [Y[first][:, 0, c0][:, None]], axis=1) * jac[:, None])
            return np.concatenate(res)

        q = adaptive_panels(proxy, th_edges, rtol=rtol, order=order, max_panels=max_panels)
        beta_all, jac_all = to_beta(q.nodes)
        W = q.weights * jac_all
        out["nodes"].append(len(q.nodes))
        mats = {k: np.zeros((J, J), dtype=complex) for k in names}
        diags = {k: np.zeros(J, dtype=complex) for k in names}
        spec = {"rod": ("u", "u"), "psiF": ("psi", "F"), "psiM": ("psi", "M"), "dpsiF": ("dpsi", "F"), "wM": ("w", "M")}
        for lo in range(0, len(beta_all), block):
            sl = slice(lo, lo + block)
            beta, w = beta_all[sl], W[sl]
            Y, diag, rowd, U = nodes(g, beta)
            for k in names:
                r, l_ = spec[k]
                mats[k] += (U[r] * w[:, None, None]).reshape(-1, J).T @ Y[l_].reshape(-1, J)
                if rowd[k] is not None:
                    mats[k][static] += w @ rowd[k]
                diags[k] += w @ diag[k]
        P = cell.period
        for k in names:
            A = -mats[k] / (2 * np.pi * P)
            A[np.arange(J), np.arange(J)] = diags[k] / (2 * np.pi)
            out[k] = A
    return out


@functools.lru_cache(maxsize=16)
def cell_head_table(head: CellHead, speed: float, harmonics: int, rtol: float = 1e-4) -> HeadTable:
    """The head's moving receptances over the cell's harmonics q Omega_P, abs(q) <= J (cached per argument set).

    Parameters
    ----------
    head : CellHead
    speed : float
        V [m/s], > 0.
    harmonics : int
        J [-], >= 0: the harmonics of Omega_P = 2 pi V / P (the force table's J = N K over the cell).
    rtol : float
        Relative tolerance of the wavenumber rule [-].

    Returns
    -------
    HeadTable
        fraction 0, harmonics J; A_Q, A_P [m/N] and E_P [1/N] of shape (2 J + 1, 2 J + 1).
    """
    if int(harmonics) != harmonics or harmonics < 0:
        raise ValueError(f"harmonics = {harmonics!r} is not allowed: it must be an integer >= 0.")
    J = int(harmonics)
    js = np.arange(-J, J + 1)
    kinds = ("rod", "psiM", "psiF", "dpsiF") if head.bending else ("rod",)
    m = cell_head_matrix(head, speed, 0.0, js, kinds, rtol)
    e = head.head_height
    A_Q = m["rod"] + (e * e * m["psiM"] if head.bending else 0)
    A_P = e * m["psiF"] if head.bending else np.zeros_like(m["rod"])
    E_P = e * m["dpsiF"] if head.bending else np.zeros_like(m["rod"])
    return HeadTable(float(speed), 0.0, J, A_Q, A_P, E_P, tuple(m["nodes"]))


def cell_head_operator(head: CellHead, speed: float, harmonics: int, rtol: float = 1e-4) -> HeadOperator:
    """The HeadOperator of the cell's period P (one table over its harmonics: rail.creepage.rail_flexibility.HeadOperator with
    bays = 1 and spacing = P, the march's samples over the cell).

    Parameters
    ----------
    head : CellHead
    speed : float
        V [m/s], > 0.
    harmonics : int
        J, the harmonics of Omega_P [-] (the force table's).
    rtol : float
        Relative tolerance of the wavenumber rule [-].

    Returns
    -------
    HeadOperator
    """
    if not math.isfinite(speed) or speed <= 0:
        raise ValueError(f"speed = {speed!r} m/s is not allowed: it must be a finite number > 0.")
    return HeadOperator((cell_head_table(head, float(speed), int(harmonics), rtol),), 1, head.cell.period)


# The cost of cell_head_table: seconds x attachments x harmonics^1.8 on one core of the 2-core machine of
# docs/cluster.md, fitted to the irregular track's cells at 40 m/s, K = 36: 23 s for 2 bays (145 harmonics,
# 4 attachments) and about 9 min for 8 bays (577 harmonics, 8 attachments); the 8-bay damper cell of the mitigation
# study at 60 m/s (1,025 harmonics, 16 attachments), 2,331 s for its whole spectrum by the probes, is below it
TABLE_SECONDS = 7.4e-4


def table_seconds(head, harmonics: int) -> float:
    """Estimated CPU seconds of cell_head_table (the cluster runtime of the jobs that build it, rail.setup.plan).

    The rod's and the beam's narrow peaks at every harmonic set the wavenumber nodes, and each node adds a product of
    the attachments' reactions over the harmonics: measured to grow as Q (2 J + 1)^1.8 (TABLE_SECONDS).

    Parameters
    ----------
    head : CellHead or None
        The cell's head (anything else: no table, 0 s).
    harmonics : int
        J [-], the cell's harmonics (N K).

    Returns
    -------
    float
        [s] on one core.
    """
    if not isinstance(head, CellHead):
        return 0.0
    return TABLE_SECONDS * len(head.cell.positions) * (2 * int(harmonics) + 1) ** 1.8


def cell_memory_mb(scn, base: float, per_harmonic: float) -> int:
    """Memory of a workflow job on the scenario [MB]: ``base``, and on a track cell with the rail's flexibility
    ``per_harmonic`` MB per harmonic of the cell (2 N K + 1) for the head's table and the linear spectrum's basis of
    u_bar over the cell (measured on the irregular track's 8-bay cells, 577 harmonics: the growth jobs 1,838-2,353 MB
    and the stiff-pad spectrum 3,382 MB peak RSS, docs/cluster.md; the rules take 2.0 and 4.5 MB per harmonic).

    Parameters
    ----------
    scn : rail.scenario.Scenario
        Its material's rail_flexibility, roughness period N [bays] and harmonics K per bay.
    base : float
        The job's memory without a cell head [MB].
    per_harmonic : float
        MB per harmonic of the cell [MB].

    Returns
    -------
    int
        [MB].
    """
    if not isinstance(scn.material.rail_flexibility, CellHead):
        return int(base)
    return int(base + per_harmonic * (2 * scn.roughness.bays * scn.harmonics + 1))
