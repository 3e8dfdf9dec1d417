"""Independent finite-element reference model of a discretely supported railway track.

Written without reference to ``rail/`` so that it can be used to verify the code under test.

Model
-----
* Rail: finite Timoshenko beam, 2-node "interdependent interpolation" elements (IIE,
  Friedman & Kosmatka 1993, Reddy 1997).  Dofs per node: (w, theta), w positive downwards
  (in the direction of a positive load), theta the rotation of the cross-section with
  w' = theta + gamma (gamma = shear strain).  The shape functions are the exact homogeneous
  solutions of the static Timoshenko beam, so the element stiffness is exact for nodal loads.
  The consistent mass matrix (translational rho*A and rotary rho*I inertia) is obtained by
  Gauss quadrature of the same shape functions (exact: the integrands are polynomials).
* Supports at x_j = j*L (j = 0..n_bays), always at nodes: railpad spring k_pad + dashpot c_pad
  between the rail and a sleeper mass m_sleeper (one vertical dof), ballast spring k_ballast +
  dashpot c_ballast between the sleeper and the ground.
* Rail damping: Kelvin-Voigt, C_rail = tau_rail * K_rail.
* Time integration: Newmark average acceleration (gamma = 1/2, beta = 1/4), fixed dt, the
  effective matrix is factorised once with scipy.sparse.linalg.splu.
* Moving load F(t) = F0 cos(2 pi f_load t + phase) at x_F(t) = x_start + V t, applied as consistent nodal
  loads (values of the displacement shape functions at the load point); the displacement under
  the load is interpolated with the same shape functions.

Caveats (measured with the Table 1 values, V = 40 m/s, 100 bays, 10 elements/bay, dt = 5e-5 s)
------------------------------------------------------------------------------------------
* Interpolated displacement under the load ('w') misses the local clamped-clamped deflection of
  the loaded element, F*(le^3/(192 EI) + le/(4 kappa G A)) at mid-element, i.e. it is too small by
  up to ~0.6 % for 10 elements/bay (0.6 m bays), with a ripple of period le/V.  'w_local' adds the
  exact static correction; nodal displacements are exact for any element count (statics).
* Start-up transient, constant load (static start + quasi-static velocity): max 0.4 % of the
  steady deflection; < 0.1 % after ~7.5 ms (0.3 m), < 0.01 % after ~21 ms (0.85 m).
  Harmonic load (stationary harmonic steady-state start): 100-300 Hz: < 0.1 % after ~10-14 ms,
  < 0.01 % after ~27 ms; at 1000-1070 Hz (lightly damped rail vibration between sleepers,
  rail loss factor 0.01 at 1 kHz) the transient decays slowly: < 1 % of the steady amplitude
  only after ~50-70 ms (2-3 m of travel), < 0.1 % after ~0.11-0.13 s.  Compare only after it.
* Track-end effects: 60 vs 100 bays (load in the middle) differ by < 2e-6 relative; 20 bays by
  ~6e-5.  Free and pinned ends are equivalent for long tracks.

Units SI.  Parameters are passed as a dict with keys
E, G, rho, A, I, kappa, L, k_pad, c_pad, m_sleeper, k_ballast, c_ballast, tau_rail.

A cell of supports with their own properties (track issue 34)
------------------------------------------------------------
``make_cell(params, positions, period, supports, dampers)`` describes a pattern of N supports at arbitrary
positions s_j in [0, P), each with its own k_pad, c_pad, m_sleeper, k_ballast, c_ballast, and rail dampers
(mass m_D on a spring k_D with a dashpot c_D, fixed to the rail), repeated with period P.  Every function
taking ``cell=`` then builds a CellTrack of n_bays *cells* (supports at m P + s_j, 0 <= m P + s_j <= n_bays P).
The mesh (cell_mesh) cuts the cell at every attachment (and at ``extra_nodes``) and divides each segment of
length l into ceil(l / h) equal elements, h = (P/N) / elements_per_bay, so every support is a node and a
uniform cell reproduces the Track mesh.  The uniform Track itself (cell=None) is unchanged.
``wheel_force_smooth_rail`` gives the force of one wheel over a smooth rail on such a track;
``harmonic_receptance`` the frequency-domain response of the same K, C, M.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.integrate
import scipy.sparse as sp
import scipy.sparse.linalg as spla

__all__ = [
    "default_params",
    "element_shape_functions",
    "element_matrices",
    "element_stiffness_closed_form",
    "assemble",
    "static_deflection",
    "static_under_load",
    "static_under_load_many",
    "local_fixed_fixed_deflection",
    "moving_load",
    "moving_wheel",
    "make_cell",
    "cell_mesh",
    "CellTrack",
    "wheel_force_smooth_rail",
    "harmonic_receptance",
    "winkler_timoshenko_deflection",
    "winkler_euler_bernoulli_deflection",
]


def default_params() -> dict:
    """Table 1 values plus the viscous dashpots suggested for the verification."""
    k_pad = 3.5e8
    k_ballast = 50e6
    return dict(
        E=2.1e11,
        G=0.81e11,
        rho=7850.0,
        A=7.69e-3,
        I=30.55e-6,
        kappa=0.4,
        L=0.6,
        k_pad=k_pad,
        c_pad=0.25 * k_pad / (2 * math.pi * 500.0),
        m_sleeper=162.0,
        k_ballast=k_ballast,
        c_ballast=1.0 * k_ballast / (2 * math.pi * 100.0),
        tau_rail=0.01 / (2 * math.pi * 1000.0),
    )


# ----------------------------------------------------------------------------------------------
# Element
# ----------------------------------------------------------------------------------------------
def _phi(params: dict, le: float) -> float:
    return 12.0 * params["E"] * params["I"] / (params["kappa"] * params["G"] * params["A"] * le**2)


def element_shape_functions(xi, le: float, phi: float):
    """IIE shape functions at local coordinate(s) xi in [0, 1].

    Returns (Nw, dNw_dx, Nt, dNt_dx), each of shape (..., 4) for the element dofs
    (w1, theta1, w2, theta2).
    """
    p = phi
    d = 1.0 + p
    if np.ndim(xi) == 0:  # fast scalar path (used once or twice per time step)
        x1 = float(xi)
        x2, x3 = x1 * x1, x1 * x1 * x1
        Nw = np.array(
            [
                (2 * x3 - 3 * x2 - p * x1 + 1 + p) / d,
                le * (x3 - (2 + p / 2) * x2 + (1 + p / 2) * x1) / d,
                -(2 * x3 - 3 * x2 - p * x1) / d,
                le * (x3 - (1 - p / 2) * x2 - (p / 2) * x1) / d,
            ]
        )
        dNw = np.array(
            [
                (6 * x2 - 6 * x1 - p) / d / le,
                (3 * x2 - (4 + p) * x1 + (1 + p / 2)) / d,
                -(6 * x2 - 6 * x1 - p) / d / le,
                (3 * x2 - (2 - p) * x1 - p / 2) / d,
            ]
        )
        Nt = np.array(
            [
                6 * (x2 - x1) / (d * le),
                (3 * x2 - (4 + p) * x1 + 1 + p) / d,
                -6 * (x2 - x1) / (d * le),
                (3 * x2 - (2 - p) * x1) / d,
            ]
        )
        dNt = np.array(
            [
                6 * (2 * x1 - 1) / (d * le**2),
                (6 * x1 - (4 + p)) / d / le,
                -6 * (2 * x1 - 1) / (d * le**2),
                (6 * x1 - (2 - p)) / d / le,
            ]
        )
        return Nw, dNw, Nt, dNt
    xi = np.asarray(xi, dtype=float)[..., None]
    x2, x3 = xi**2, xi**3
    Nw = np.concatenate(
        [
            (2 * x3 - 3 * x2 - p * xi + 1 + p) / d,
            le * (x3 - (2 + p / 2) * x2 + (1 + p / 2) * xi) / d,
            -(2 * x3 - 3 * x2 - p * xi) / d,
            le * (x3 - (1 - p / 2) * x2 - (p / 2) * xi) / d,
        ],
        axis=-1,
    )
    dNw = np.concatenate(
        [
            (6 * x2 - 6 * xi - p) / d / le,
            (3 * x2 - (4 + p) * xi + (1 + p / 2)) / d,
            -(6 * x2 - 6 * xi - p) / d / le,
            (3 * x2 - (2 - p) * xi - p / 2) / d,
        ],
        axis=-1,
    )
    Nt = np.concatenate(
        [
            6 * (x2 - xi) / (d * le),
            (3 * x2 - (4 + p) * xi + 1 + p) / d,
            -6 * (x2 - xi) / (d * le),
            (3 * x2 - (2 - p) * xi) / d,
        ],
        axis=-1,
    )
    dNt = np.concatenate(
        [
            6 * (2 * xi - 1) / (d * le**2),
            (6 * xi - (4 + p)) / d / le,
            -6 * (2 * xi - 1) / (d * le**2),
            (6 * xi - (2 - p)) / d / le,
        ],
        axis=-1,
    )
    return Nw, dNw, Nt, dNt


def element_matrices(params: dict, le: float):
    """Element stiffness and consistent mass (with rotary inertia), by exact Gauss quadrature."""
    E, G, rho, A, I, kappa = (params[k] for k in ("E", "G", "rho", "A", "I", "kappa"))
    phi = _phi(params, le)
    gp, gw = np.polynomial.legendre.leggauss(6)  # exact for polynomials up to degree 11
    xi = 0.5 * (gp + 1.0)
    wq = 0.5 * gw * le
    Nw, dNw, Nt, dNt = element_shape_functions(xi, le, phi)
    gam = dNw - Nt
    Ke = E * I * np.einsum("q,qi,qj->ij", wq, dNt, dNt) + kappa * G * A * np.einsum("q,qi,qj->ij", wq, gam, gam)
    Me = rho * A * np.einsum("q,qi,qj->ij", wq, Nw, Nw) + rho * I * np.einsum("q,qi,qj->ij", wq, Nt, Nt)
    return 0.5 * (Ke + Ke.T), 0.5 * (Me + Me.T)


def element_stiffness_closed_form(params: dict, le: float) -> np.ndarray:
    """Textbook closed-form IIE Timoshenko stiffness (used only to self-check the quadrature)."""
    phi = _phi(params, le)
    c = params["E"] * params["I"] / ((1 + phi) * le**3)
    return c * np.array(
        [
            [12, 6 * le, -12, 6 * le],
            [6 * le, (4 + phi) * le**2, -6 * le, (2 - phi) * le**2],
            [-12, -6 * le, 12, -6 * le],
            [6 * le, (2 - phi) * le**2, -6 * le, (4 + phi) * le**2],
        ]
    )


# ----------------------------------------------------------------------------------------------
# Assembly
# ----------------------------------------------------------------------------------------------
class Track:
    """Assembled finite track.  Global dof order: rail (w0, t0, w1, t1, ...), then sleepers."""

    def __init__(self, params: dict, n_bays: int, elements_per_bay: int, ends: str = "free"):
        if n_bays < 1 or elements_per_bay < 1:
            raise ValueError("n_bays and elements_per_bay must be >= 1")
        if ends not in ("free", "pinned"):
            raise ValueError("ends must be 'free' or 'pinned'")
        self.params = dict(params)
        self.L = float(params["L"])
        self.n_bays = int(n_bays)
        self.epb = int(elements_per_bay)
        self.n_el = self.n_bays * self.epb
        self.le = self.L / self.epb
        self.phi = _phi(params, self.le)
        self.n_nodes = self.n_el + 1
        self.x_nodes = np.arange(self.n_nodes) * self.le
        self.n_sleepers = self.n_bays + 1
        self.n_rail = 2 * self.n_nodes
        self.ndof = self.n_rail + self.n_sleepers
        self.support_nodes = np.arange(self.n_sleepers) * self.epb
        self.sleeper_dofs = self.n_rail + np.arange(self.n_sleepers)

        Ke, Me = element_matrices(params, self.le)
        e = np.arange(self.n_el)
        edofs = np.stack([2 * e, 2 * e + 1, 2 * e + 2, 2 * e + 3], axis=1)  # (n_el, 4)
        rows = np.repeat(edofs, 4, axis=1).ravel()
        cols = np.tile(edofs, (1, 4)).ravel()
        N = self.ndof
        K_rail = sp.coo_matrix((np.tile(Ke.ravel(), self.n_el), (rows, cols)), shape=(N, N)).tocsr()
        M_rail = sp.coo_matrix((np.tile(Me.ravel(), self.n_el), (rows, cols)), shape=(N, N)).tocsr()

        # supports: rail w dof r, sleeper dof s
        r = 2 * self.support_nodes
        s = self.sleeper_dofs

        def spring(kp, kb):
            rr = np.concatenate([r, r, s, s, s])
            cc = np.concatenate([r, s, r, s, s])
            vv = np.concatenate(
                [np.full(r.size, kp), np.full(r.size, -kp), np.full(r.size, -kp), np.full(r.size, kp), np.full(r.size, kb)]
            )
            return sp.coo_matrix((vv, (rr, cc)), shape=(N, N)).tocsr()

        K_sup = spring(params["k_pad"], params["k_ballast"])
        C_sup = spring(params["c_pad"], params["c_ballast"])
        M_sl = sp.coo_matrix((np.full(s.size, params["m_sleeper"]), (s, s)), shape=(N, N)).tocsr()

        self.K = (K_rail + K_sup).tocsc()
        self.C = (params["tau_rail"] * K_rail + C_sup).tocsc()
        self.M = (M_rail + M_sl).tocsc()

        fixed = np.array([0, 2 * (self.n_nodes - 1)]) if ends == "pinned" else np.array([], dtype=int)
        self.free = np.setdiff1d(np.arange(N), fixed)
        if fixed.size:
            idx = self.free
            self.K = self.K[idx][:, idx].tocsc()
            self.C = self.C[idx][:, idx].tocsc()
            self.M = self.M[idx][:, idx].tocsc()
        self._pos = -np.ones(N, dtype=int)
        self._pos[self.free] = np.arange(self.free.size)
        self.n = self.free.size

    # -- load / interpolation ------------------------------------------------------------------
    def locate(self, x: float):
        """Element index and local coordinate of position x (clipped into the beam)."""
        total = self.n_el * self.le
        if x < -1e-12 * total or x > total * (1 + 1e-12):
            raise ValueError(f"position {x} outside the beam [0, {total}]")
        e = int(min(max(math.floor(x / self.le), 0), self.n_el - 1))
        xi = min(max((x - e * self.le) / self.le, 0.0), 1.0)
        return e, xi

    def load_pattern(self, x: float):
        """(reduced dof indices, Nw values, dNw/dx values) for a unit load at x."""
        e, xi = self.locate(x)
        Nw, dNw, _, _ = element_shape_functions(xi, self.le, self.phi)
        gd = np.array([2 * e, 2 * e + 1, 2 * e + 2, 2 * e + 3])
        pos = self._pos[gd]
        keep = pos >= 0
        return pos[keep], Nw[keep], dNw[keep], pos, Nw

    def interp(self, u: np.ndarray, x: float) -> float:
        """Rail displacement at x interpolated with the element shape functions (u: reduced dofs)."""
        _, _, _, pos, Nw = self.load_pattern(x)
        keep = pos >= 0
        return float(Nw[keep] @ u[pos[keep]])

    def local_correction(self, x: float) -> float:
        """Per unit load: exact clamped-clamped deflection of the element containing x."""
        e, xi = self.locate(x)
        return local_fixed_fixed_deflection(self.params, self.le, xi * self.le)

    def full(self, u: np.ndarray) -> np.ndarray:
        out = np.zeros(self.ndof)
        out[self.free] = u
        return out

    # -- supports (the same interface as CellTrack) ----------------------------------------------
    @property
    def support_x(self) -> np.ndarray:
        return np.arange(self.n_sleepers) * self.L

    def nearest_support(self, x: float) -> int:
        return int(min(max(round(x / self.L), 0), self.n_bays))

    def support_ahead(self, x: float):
        """Index of the first support strictly ahead of x (None past the last one)."""
        j = int(math.floor(x / self.L + 1e-9)) + 1
        return j if j <= self.n_bays else None


# ----------------------------------------------------------------------------------------------
# A track periodic over a cell of supports with their own properties, and rail dampers
# ----------------------------------------------------------------------------------------------
_SUPPORT_KEYS = ("k_pad", "c_pad", "m_sleeper", "k_ballast", "c_ballast")


def make_cell(params: dict, positions, period: float, supports=None, dampers=(), extra_nodes=()) -> dict:
    """A cell: supports at ``positions`` (strictly increasing in [0, period)), repeated with period P.

    supports    : None or one dict per position overriding any of k_pad, c_pad, m_sleeper, k_ballast,
                  c_ballast of ``params`` (viscous dashpots; m_sleeper > 0)
    dampers     : dicts dict(position, mass, stiffness, c=0): a rail damper, mass m_D (> 0) on a spring k_D
                  with a dashpot c_D in parallel, fixed to the rail at ``position`` in [0, period)
    extra_nodes : further positions in [0, period) that must be nodes (e.g. mid-bay observation points)
    Returns dict(period, supports=[complete dicts with 'position'], dampers=[...], extra_nodes=[...]).
    """
    positions = np.asarray(positions, dtype=float)
    P = float(period)
    if positions.ndim != 1 or positions.size < 1:
        raise ValueError("positions must be a non-empty 1-d sequence")
    if np.any(np.diff(positions) <= 0) or positions[0] < 0 or positions[-1] >= P:
        raise ValueError(f"positions {positions.tolist()} must be strictly increasing in [0, P = {P})")
    if supports is None:
        supports = [{}] * positions.size
    if len(supports) != positions.size:
        raise ValueError("supports must have one dict per position")
    sup = []
    for s, over in zip(positions, supports):
        bad = set(over) - set(_SUPPORT_KEYS)
        if bad:
            raise ValueError(f"unknown support keys {sorted(bad)}")
        d = {k: float(params[k]) for k in _SUPPORT_KEYS}
        d.update({k: float(v) for k, v in over.items()})
        if not d["m_sleeper"] > 0:
            raise ValueError(f"m_sleeper = {d['m_sleeper']} must be > 0 (the mass matrix must be invertible)")
        d["position"] = float(s)
        sup.append(d)
    dmp = []
    for d in dampers:
        if not 0.0 <= d["position"] < P:
            raise ValueError(f"damper position {d['position']} outside [0, {P})")
        if not d["mass"] > 0:
            raise ValueError(f"damper mass {d['mass']} must be > 0")
        dmp.append(dict(position=float(d["position"]), mass=float(d["mass"]), stiffness=float(d["stiffness"]),
                        c=float(d.get("c", 0.0))))
    extra = [float(e) for e in extra_nodes]
    if any(not 0.0 <= e < P for e in extra):
        raise ValueError(f"extra_nodes {extra} must lie in [0, {P})")
    return dict(period=P, supports=sup, dampers=dmp, extra_nodes=extra)


def cell_mesh(cell: dict, elements_per_bay: int):
    """Element lengths over one cell [0, P): every support, damper and extra node is a node.

    The cell is cut at those points; a segment of length l gets max(1, ceil(l / h)) equal elements,
    h = (P / N) / elements_per_bay (N supports), so a uniform cell with one support per bay has exactly
    elements_per_bay elements per bay.  Returns (segment start positions, elements per segment).
    """
    P = cell["period"]
    pts = [s["position"] for s in cell["supports"]] + [d["position"] for d in cell["dampers"]] + cell["extra_nodes"]
    cuts = np.unique(np.concatenate([[0.0], np.asarray(pts, dtype=float), [P]]))
    seg = np.diff(cuts)
    if np.any(seg < 1e-9 * P):
        raise ValueError("two attachment points closer than 1e-9 P")
    h = P / len(cell["supports"]) / int(elements_per_bay)
    n_e = np.maximum(1, np.ceil(seg / h - 1e-9)).astype(int)
    return cuts[:-1], seg, n_e


class CellTrack:
    """Assembled finite track of ``n_cells`` cells (length n_cells P), the pattern of ``cell`` repeated.

    Same interface as Track (K, C, M, n, locate, load_pattern, interp, local_correction, full,
    sleeper_dofs, support_x, nearest_support, support_ahead).  Global dofs: rail (w, theta per node),
    then the sleepers (in order of position), then the rail-damper masses.  Supports at m P + s_j for
    every m with 0 <= m P + s_j <= n_cells P (so a support at s = 0 also closes the last cell).
    Rail dampers: mass m_D, spring k_D and dashpot c_D between the rail's w at its node and the mass.
    """

    def __init__(self, params: dict, cell: dict, n_cells: int, elements_per_bay: int, ends: str = "free"):
        if n_cells < 1 or elements_per_bay < 1:
            raise ValueError("n_cells and elements_per_bay must be >= 1")
        if ends not in ("free", "pinned"):
            raise ValueError("ends must be 'free' or 'pinned'")
        self.params = dict(params)
        self.cell = cell
        P = cell["period"]
        self.P = P
        self.n_cells = int(n_cells)
        self.L = P / len(cell["supports"])  # mean spacing
        starts, seg, n_e = cell_mesh(cell, elements_per_bay)
        le_cell = np.repeat(seg / n_e, n_e)
        x_cell = np.concatenate([starts[k] + np.arange(n_e[k]) * seg[k] / n_e[k] for k in range(seg.size)])
        self.le_el = np.tile(le_cell, self.n_cells)
        self.x_nodes = np.concatenate([m * P + x_cell for m in range(self.n_cells)] + [[self.n_cells * P]])
        self.n_el = self.le_el.size
        self.n_nodes = self.n_el + 1
        self.phi_el = np.array([_phi(params, le) for le in self.le_el])
        total = self.n_cells * P

        def node_of(xp):
            i = int(np.argmin(np.abs(self.x_nodes - xp)))
            if abs(self.x_nodes[i] - xp) > 1e-9 * P:
                raise AssertionError("attachment not at a node")
            return i

        tol = 1e-9 * P
        sup = [(m * P + s["position"], s) for m in range(self.n_cells + 1) for s in cell["supports"]
               if m * P + s["position"] <= total + tol]
        dmp = [(m * P + d["position"], d) for m in range(self.n_cells + 1) for d in cell["dampers"]
               if m * P + d["position"] <= total + tol]
        self.n_sleepers = len(sup)
        self.n_dampers = len(dmp)
        self.n_rail = 2 * self.n_nodes
        self.ndof = self.n_rail + self.n_sleepers + self.n_dampers
        self.support_nodes = np.array([node_of(xp) for xp, _ in sup], dtype=int)
        self.damper_nodes = np.array([node_of(xp) for xp, _ in dmp], dtype=int)
        self._support_x = np.array([xp for xp, _ in sup])
        self.damper_x = np.array([xp for xp, _ in dmp])
        self.sleeper_dofs = self.n_rail + np.arange(self.n_sleepers)
        self.damper_dofs = self.n_rail + self.n_sleepers + np.arange(self.n_dampers)
        N = self.ndof

        # rail: element matrices per distinct element length
        cache = {}
        rows, cols, kv, mv = [], [], [], []
        for e, le in enumerate(self.le_el):
            key = round(le / P, 12)
            if key not in cache:
                cache[key] = element_matrices(params, le)
            Ke, Me = cache[key]
            d = np.array([2 * e, 2 * e + 1, 2 * e + 2, 2 * e + 3])
            rows.append(np.repeat(d, 4))
            cols.append(np.tile(d, 4))
            kv.append(Ke.ravel())
            mv.append(Me.ravel())
        rows, cols = np.concatenate(rows), np.concatenate(cols)
        K_rail = sp.coo_matrix((np.concatenate(kv), (rows, cols)), shape=(N, N)).tocsr()
        M_rail = sp.coo_matrix((np.concatenate(mv), (rows, cols)), shape=(N, N)).tocsr()

        # point attachments: spring k (dashpot c) between rail w dof r and mass dof s, ground spring kg (cg)
        r = np.concatenate([2 * self.support_nodes, 2 * self.damper_nodes]).astype(int)
        s = np.concatenate([self.sleeper_dofs, self.damper_dofs]).astype(int)
        kp = np.array([q["k_pad"] for _, q in sup] + [q["stiffness"] for _, q in dmp])
        cp = np.array([q["c_pad"] for _, q in sup] + [q["c"] for _, q in dmp])
        kb = np.array([q["k_ballast"] for _, q in sup] + [0.0] * len(dmp))
        cb = np.array([q["c_ballast"] for _, q in sup] + [0.0] * len(dmp))
        ms = np.array([q["m_sleeper"] for _, q in sup] + [q["mass"] for _, q in dmp])

        def spring(k, kg):
            rr = np.concatenate([r, r, s, s, s])
            cc = np.concatenate([r, s, r, s, s])
            vv = np.concatenate([k, -k, -k, k, kg])
            return sp.coo_matrix((vv, (rr, cc)), shape=(N, N)).tocsr()

        self.K = (K_rail + spring(kp, kb)).tocsc()
        self.C = (params["tau_rail"] * K_rail + spring(cp, cb)).tocsc()
        self.M = (M_rail + sp.coo_matrix((ms, (s, s)), shape=(N, N)).tocsr()).tocsc()

        fixed = np.array([0, 2 * (self.n_nodes - 1)]) if ends == "pinned" else np.array([], dtype=int)
        self.free = np.setdiff1d(np.arange(N), fixed)
        if fixed.size:
            idx = self.free
            self.K = self.K[idx][:, idx].tocsc()
            self.C = self.C[idx][:, idx].tocsc()
            self.M = self.M[idx][:, idx].tocsc()
        self._pos = -np.ones(N, dtype=int)
        self._pos[self.free] = np.arange(self.free.size)
        self.n = self.free.size

    def locate(self, x: float):
        total = self.x_nodes[-1]
        if x < -1e-12 * total or x > total * (1 + 1e-12):
            raise ValueError(f"position {x} outside the beam [0, {total}]")
        e = int(min(max(np.searchsorted(self.x_nodes, x, side="right") - 1, 0), self.n_el - 1))
        xi = min(max((x - self.x_nodes[e]) / self.le_el[e], 0.0), 1.0)
        return e, xi

    def load_pattern(self, x: float):
        e, xi = self.locate(x)
        Nw, dNw, _, _ = element_shape_functions(xi, self.le_el[e], self.phi_el[e])
        gd = np.array([2 * e, 2 * e + 1, 2 * e + 2, 2 * e + 3])
        pos = self._pos[gd]
        keep = pos >= 0
        return pos[keep], Nw[keep], dNw[keep], pos, Nw

    def interp(self, u: np.ndarray, x: float) -> float:
        _, _, _, pos, Nw = self.load_pattern(x)
        keep = pos >= 0
        return Nw[keep] @ u[pos[keep]]

    def local_correction(self, x: float) -> float:
        e, xi = self.locate(x)
        return local_fixed_fixed_deflection(self.params, self.le_el[e], xi * self.le_el[e])

    def full(self, u: np.ndarray) -> np.ndarray:
        out = np.zeros(self.ndof, dtype=u.dtype)
        out[self.free] = u
        return out

    @property
    def support_x(self) -> np.ndarray:
        return self._support_x.copy()

    def nearest_support(self, x: float) -> int:
        return int(np.argmin(np.abs(self._support_x - x)))

    def support_ahead(self, x: float):
        j = int(np.searchsorted(self._support_x, x + 1e-9 * self.L, side="right"))
        return j if j < self.n_sleepers else None


def _track(params, n_bays, elements_per_bay, ends, cell):
    """Track (uniform, n_bays bays) or, with a cell, CellTrack of n_bays cells."""
    if cell is None:
        return Track(params, n_bays, elements_per_bay, ends)
    return CellTrack(params, cell, n_bays, elements_per_bay, ends)


def assemble(params: dict, n_bays: int, elements_per_bay: int, ends: str = "free", *, cell=None):
    """Track of n_bays bays, or with ``cell`` (make_cell) a CellTrack of n_bays cells."""
    return _track(params, n_bays, elements_per_bay, ends, cell)


# ----------------------------------------------------------------------------------------------
# Statics
# ----------------------------------------------------------------------------------------------
def static_deflection(params, x_load, n_bays, elements_per_bay, *, ends="free", cell=None):
    """Static deflection of the finite beam under a unit downward point load at x_load.
    With ``cell`` (make_cell) the track is n_bays cells of that pattern (here and in every function below).

    Returns (x_nodes, w_nodes): rail node positions and the rail vertical displacement there
    (m per N, positive downwards).
    """
    tr = _track(params, n_bays, elements_per_bay, ends, cell)
    u = _static_solution(tr, x_load, 1.0)
    return tr.x_nodes.copy(), tr.full(u)[0 : tr.n_rail : 2].copy()


def static_under_load(params, x_load, n_bays, elements_per_bay, *, ends="free", local_correction=False,
                      cell=None) -> float:
    """Static rail deflection directly under a unit load at x_load, interpolated with the
    element shape functions (the same quantity moving_load returns in 'w').  With
    local_correction=True the exact clamped-clamped element deflection is added, which makes the
    result the exact static deflection of the finite beam (independent of elements_per_bay)."""
    tr = _track(params, n_bays, elements_per_bay, ends, cell)
    w = tr.interp(_static_solution(tr, x_load, 1.0), x_load)
    if local_correction:
        w += tr.local_correction(x_load)
    return w


def static_under_load_many(params, xs, n_bays, elements_per_bay, *, ends="free", local_correction=False, cell=None):
    """static_under_load for many load positions with a single factorisation of K."""
    tr = _track(params, n_bays, elements_per_bay, ends, cell)
    lu = spla.splu(tr.K)
    out = np.empty(len(xs))
    f = np.zeros(tr.n)
    for i, x in enumerate(xs):
        idx, Nw, _, _, _ = tr.load_pattern(x)
        f[:] = 0.0
        f[idx] = Nw
        out[i] = tr.interp(lu.solve(f), x)
        if local_correction:
            out[i] += tr.local_correction(x)
    return out


def local_fixed_fixed_deflection(params, le: float, a: float) -> float:
    """Exact static deflection under a unit point load at distance a from the left end of a
    Timoshenko beam segment of length le clamped (w = theta = 0) at both ends.

    This is exactly the part of the true static deflection under a load inside an element that
    the shape-function interpolation misses (the IIE shape functions are exact homogeneous
    solutions, so nodal values are exact and interpolation + this term is the exact deflection).
    Computed by splitting the segment into two IIE elements of lengths a and le - a (exact for
    nodal loads).  Centre load check: le^3/(192 EI) + le/(4 kappa G A).
    """
    b = le - a
    if min(a, b) <= 1e-9 * le:
        return 0.0
    Ka = element_stiffness_closed_form(params, a)
    Kb = element_stiffness_closed_form(params, b)
    Kc = Ka[2:, 2:] + Kb[:2, :2]
    return float(np.linalg.solve(Kc, np.array([1.0, 0.0]))[0])


def _static_solution(tr: Track, x_load: float, F: float) -> np.ndarray:
    idx, Nw, _, _, _ = tr.load_pattern(x_load)
    f = np.zeros(tr.n)
    f[idx] = F * Nw
    return spla.spsolve(tr.K, f)


# ----------------------------------------------------------------------------------------------
# Dynamics
# ----------------------------------------------------------------------------------------------
def moving_load(
    params,
    speed,
    f_load,
    n_bays,
    elements_per_bay,
    dt,
    x_start,
    x_end,
    F0=1.0,
    *,
    ends="free",
    quasi_static_start=True,
    duration=None,
    sleeper_x=None,
    phase=0.0,
    cell=None,
):
    """Newmark (average acceleration) integration of a moving point load.

    The load F(t) = F0 cos(2 pi f_load t + phase) moves from x_start to x_end at constant `speed`
    (m/s; must be > 0 unless `duration` is given, in which case the load may be stationary).
    Initial state: the steady state of a stationary load at x_start - for f_load = 0 the static
    equilibrium K u = f, for f_load > 0 the harmonic steady state
    u = Re[(K - w^2 M + i w C)^-1 f e^{i phase}].  With quasi_static_start=True the velocity due to
    the motion of that steady state, V * d/dx_F u, is added (one-sided derivative in the element
    containing x_start); the initial acceleration follows from the equation of motion.  Both
    reduce the start-up transient; they do not remove it (see module caveats).

    Returns dict with
      t                : times (s), t[0] = 0
      x                : load positions (m)
      w                : rail displacement under the load (m, positive downwards), interpolated
                         with the element shape functions
      w_local          : w + F(t) * (clamped-clamped element deflection under the load); the
                         quasi-static local correction that removes the O(element length)
                         shear-deformation error of the interpolation (see
                         local_fixed_fixed_deflection)
      F                : load values (N)
      w_sleeper_ahead  : displacement of the first sleeper strictly ahead of the load (m)
      w_sleeper_fixed  : displacement history of the sleeper nearest `sleeper_x`
                         (default (x_start + x_end)/2) and x_sleeper_fixed, its position
      dt, n_dof
    With ``cell`` (make_cell) the track is n_bays cells of that pattern.
    """
    tr = _track(params, n_bays, elements_per_bay, ends, cell)
    if duration is None:
        if speed <= 0:
            raise ValueError("speed must be > 0 unless duration is given")
        n_steps = int(round((x_end - x_start) / (speed * dt)))
    else:
        n_steps = int(round(duration / dt))
    if n_steps < 1:
        raise ValueError("no time steps")
    t = np.arange(n_steps + 1) * dt
    x = x_start + speed * t
    om = 2 * math.pi * f_load
    F = F0 * np.cos(om * t + phase)

    K, C, M = tr.K, tr.C, tr.M
    n = tr.n

    # initial conditions: steady state of the STATIONARY load at x_start (static equilibrium for
    # f_load = 0, the stationary harmonic steady state otherwise), plus, if quasi_static_start,
    # the velocity caused by the motion of that steady state, V * d/dx_F (...), at t = 0.
    idx0, Nw0, dNw0, _, _ = tr.load_pattern(x[0])
    n0 = np.zeros(n)
    n0[idx0] = Nw0
    dn0 = np.zeros(n)
    dn0[idx0] = dNw0
    if om == 0.0:
        H_lu = spla.splu(K)
        U = H_lu.solve(n0) * F0
        dU = H_lu.solve(dn0) * F0 if quasi_static_start else np.zeros(n)
    else:
        H_lu = spla.splu((K - om**2 * M + 1j * om * C).tocsc().astype(complex))
        U = H_lu.solve(n0.astype(complex)) * F0
        dU = H_lu.solve(dn0.astype(complex)) * F0 if quasi_static_start else np.zeros(n, complex)
    ph = np.exp(1j * phase)
    u = np.real(U * ph)
    v = np.real(1j * om * U * ph) + speed * np.real(dU * ph)
    f0 = F[0] * n0
    a = spla.splu(M).solve(f0 - C @ v - K @ u)
    del H_lu

    c0 = 4.0 / dt**2
    c1 = 2.0 / dt
    Keff = (K + c1 * C + c0 * M).tocsc()
    lu = spla.splu(Keff)

    sl_r = tr._pos[tr.sleeper_dofs]  # reduced index of sleeper dofs (never fixed)
    if sleeper_x is None:
        sleeper_x = 0.5 * (x_start + x_end)
    j_fix = tr.nearest_support(sleeper_x)

    w = np.empty(n_steps + 1)
    w_loc = np.empty(n_steps + 1)
    ws_ahead = np.full(n_steps + 1, np.nan)
    ws_fix = np.empty(n_steps + 1)

    def record(i, u):
        w[i] = tr.interp(u, x[i])
        w_loc[i] = w[i] + F[i] * tr.local_correction(x[i])
        j = tr.support_ahead(x[i])
        if j is not None:
            ws_ahead[i] = u[sl_r[j]]
        ws_fix[i] = u[sl_r[j_fix]]

    record(0, u)
    f = np.zeros(n)
    for i in range(1, n_steps + 1):
        idx, Nw, _, _, _ = tr.load_pattern(x[i])
        f[:] = 0.0
        f[idx] = F[i] * Nw
        rhs = f + M @ (c0 * u + (4.0 / dt) * v + a) + C @ (c1 * u + v)
        u_new = lu.solve(rhs)
        v_new = c1 * (u_new - u) - v
        a = c0 * (u_new - u) - (4.0 / dt) * v - a
        u, v = u_new, v_new
        record(i, u)

    return {
        "t": t,
        "x": x,
        "w": w,
        "w_local": w_loc,
        "F": F,
        "w_sleeper_ahead": ws_ahead,
        "w_sleeper_fixed": ws_fix,
        "x_sleeper_fixed": tr.support_x[j_fix],
        "dt": dt,
        "n_dof": n,
    }


def moving_wheel(params, speed, n_bays, elements_per_bay, dt, x_start, x_end, *, wheel_mass, static_load,
                 hertz_stiffness, roughness, ends="free", local_correction=True, cell=None):
    """A rigid wheel rolling at constant speed on the finite-element track, coupled through a linear
    contact spring over a roughness: Newmark (average acceleration) for rail and wheel together.

    Downwards positive for the wheel z and the rail; the roughness r(x) is a height (upwards):
        P = k_H (z - w_c + r(x)),   m z'' = W - P,   M u'' + C u' + K u = N(x) P,
        w_c = N(x)^T u + c_loc(x) P,
    c_loc the exact clamped-clamped element deflection under the load (local_fixed_fixed_deflection):
    the quasi-static local shear deformation the element interpolation misses, which with 10
    elements per bay is about 8 % of the contact spring's compliance. Each step is one scalar
    equation for P (the rail's response to the load pattern by one extra solve).

    Initial state: static equilibrium at x_start (P = W, wheel at rest); the start-up transient
    decays over a few bays. Returns dict with x (load positions, m), P (contact force, N), t.
    With ``cell`` (make_cell) the track is n_bays cells of that pattern.
    """
    tr = _track(params, n_bays, elements_per_bay, ends, cell)
    n_steps = int(round((x_end - x_start) / (speed * dt)))
    t = np.arange(n_steps + 1) * dt
    x = x_start + speed * t
    K, C, M = tr.K, tr.C, tr.M
    n = tr.n
    W, m, kH = float(static_load), float(wheel_mass), float(hertz_stiffness)

    def pattern(xx):
        idx, Nw, _, _, _ = tr.load_pattern(xx)
        v = np.zeros(n)
        v[idx] = Nw
        return v

    def cloc(xx):
        return tr.local_correction(xx) if local_correction else 0.0

    N0 = pattern(x[0])
    u = spla.splu(K).solve(N0 * W)
    v = np.zeros(n)
    a = np.zeros(n)  # static equilibrium: M a = N W - K u = 0
    z = N0 @ u + cloc(x[0]) * W + W / kH - roughness(x[0])
    zv, za = 0.0, 0.0
    c0, c1 = 4.0 / dt**2, 2.0 / dt
    lu = spla.splu((K + c1 * C + c0 * M).tocsc())
    P = np.empty(n_steps + 1)
    P[0] = W
    for i in range(1, n_steps + 1):
        Ni = pattern(x[i])
        u_hat = lu.solve(M @ (c0 * u + (4.0 / dt) * v + a) + C @ (c1 * u + v))
        g = lu.solve(Ni)
        z_hat = z + dt * zv + za / c0
        comp = Ni @ g + cloc(x[i])
        Pi = kH * (z_hat + W / (m * c0) - Ni @ u_hat + roughness(x[i])) / (1.0 + kH / (m * c0) + kH * comp)
        u_new = u_hat + g * Pi
        v_new = c1 * (u_new - u) - v
        a = c0 * (u_new - u) - (4.0 / dt) * v - a
        u, v = u_new, v_new
        za_new = (W - Pi) / m
        z = z_hat + (W - Pi) / (m * c0)
        zv = zv + 0.5 * dt * (za + za_new)
        za = za_new
        P[i] = Pi
    return {"t": t, "x": x, "P": P}


def wheel_force_smooth_rail(params, cell, speed, n_cells, elements_per_bay, dt, x_start, x_end, *, wheel_mass,
                            static_load, hertz_stiffness, ends="free", local_correction=True):
    """Contact force of one rigid wheel rolling at constant speed over a smooth rail on a track of n_cells
    cells of ``cell`` (make_cell): moving_wheel with zero roughness (see there for the model and the start).

    Past the start-up transient the force is periodic with the cell's passing period P / V.  Returns dict
    with t (s), x (wheel positions, m), P (contact force, N).

    Accuracy, measured on one voided sleeper in 4 bays (ballast x 1e-3 at support 1), V = 40 m/s, force
    fluctuation 27 kN; harmonics k = 1..24 of the cell-passing frequency over one cell, errors relative to the
    largest harmonic (4.3 kN):
    * time step (8 elements/bay): 6.4e-4, 1.6e-4, 3.7e-5, 7.5e-6 for dt = 1e-4, 5e-5, 2.5e-5, 1.25e-5 s
      (second order);
    * elements (dt = 2.5e-5 s, against 32/bay): 7.3e-3, 4.0e-5, 5.2e-6 for 4, 8, 16 per bay.  The load moving
      over the nodes adds spurious harmonics at multiples of the element-passing frequency V / l_e (harmonic
      4 N_bays x elements_per_bay of the cell: 31 N at k = 16 with 4 per bay, 38 N at k = 32 with 16 per bay),
      so compare only harmonics well below it (the 4-per-bay error above is its k = 16 line);
    * start-up (static start 3 cells before): the cell analysed differs from the cell after it by 1.8e-1,
      1.4e-2, 1.1e-3 for 0, 1, 2 cells of run-in: about a factor 12 per 2.4 m cell, so start at least
      5-6 cells before the analysed one for 1e-5..1e-6.
    The time record also carries a ~11-13 kHz oscillation of about 0.25 % of the fluctuation that depends on
    dt (Newmark average acceleration does not damp it); judge the force by its harmonics, not sample by sample.
    """
    return moving_wheel(params, speed, n_cells, elements_per_bay, dt, x_start, x_end, wheel_mass=wheel_mass,
                        static_load=static_load, hertz_stiffness=hertz_stiffness, roughness=lambda x: 0.0,
                        ends=ends, local_correction=local_correction, cell=cell)


def harmonic_receptance(params, x_obs, x0, omega, n_bays, elements_per_bay, *, ends="free", cell=None):
    """Frequency-domain receptance of the finite FE track, (K - omega^2 M + i omega C)^-1 for a unit force at x0,
    the rail displacement at each x_obs interpolated with the shape functions (exact only at nodes: put x0 and
    x_obs at nodes, e.g. with make_cell(extra_nodes=...)).  Viscous damping as in the time domain.
    x_obs 1-d array, x0 and omega scalars; returns complex array (m/N).
    """
    tr = _track(params, n_bays, elements_per_bay, ends, cell)
    idx, Nw, _, _, _ = tr.load_pattern(x0)
    f = np.zeros(tr.n, complex)
    f[idx] = Nw
    u = spla.spsolve((tr.K - omega**2 * tr.M + 1j * omega * tr.C).tocsc(), f)
    return np.array([tr.interp(u, float(x)) for x in np.atleast_1d(x_obs)])


# ----------------------------------------------------------------------------------------------
# Closed forms for a continuous Winkler foundation (static, point load F at x = 0)
# ----------------------------------------------------------------------------------------------
def _winkler_modulus(params):
    kp, kb = params["k_pad"], params["k_ballast"]
    return kp * kb / (kp + kb) / params["L"]


def winkler_euler_bernoulli_deflection(params, F=1.0) -> float:
    """w(0) = F / (8 EI lam^3), lam = (s / 4EI)^(1/4), s = k_eff / L."""
    EI = params["E"] * params["I"]
    s = _winkler_modulus(params)
    lam = (s / (4 * EI)) ** 0.25
    return F / (8 * EI * lam**3)


def winkler_timoshenko_deflection(params, F=1.0) -> float:
    """Timoshenko beam on a Winkler foundation (foundation acting on w), point load F:
    w(0) = (1/pi) int_0^inf F / (EI xi^4 / (1 + EI xi^2 / (kappa G A)) + s) dxi."""
    EI = params["E"] * params["I"]
    kGA = params["kappa"] * params["G"] * params["A"]
    s = _winkler_modulus(params)
    lam = (s / (4 * EI)) ** 0.25

    def integrand(q):  # q = xi / lam
        xi = q * lam
        return lam / (EI * xi**4 / (1 + EI * xi**2 / kGA) + s)

    val, _ = scipy.integrate.quad(integrand, 0, np.inf, epsabs=0, epsrel=1e-12, limit=400)
    return F * val / math.pi
