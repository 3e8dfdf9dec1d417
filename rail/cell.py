"""A track whose period is a cell of N bays with supports of their own (docs/track.md, "A cell of N bays").

Real track is not identical bay by bay: sleeper spacing varies, a sleeper hangs (voided), a pad is
stiffer or worn, rail dampers are fitted.  Here the track is periodic over a *cell* of length P
holding N supports at positions s_0 = 0 < s_1 < ... < s_{N-1} < P, each with its own pad, sleeper
mass and ballast, and optionally rail dampers (a mass on a spring fixed to the rail).  Every point
attachment acts on the rail through a dynamic stiffness K_j(omega) (force on the rail -K_j w(s_j)),
so supports and dampers enter the same equations.  The uniform track of rail.track is the cell of
one support (``TrackCell.uniform``); a cell of N identical supports at equal spacing is the same
track seen over N bays.

Conventions as rail.track: time dependence exp(i omega t), W(beta) = int w(x) exp(i beta x) dx,
displacement and forces positive downwards.  The cell wavenumber is beta_P = 2 pi / P.

A voided sleeper is a support with a very soft ballast (e.g. 1e-3 of the nominal stiffness).  The
model is linear: a real voided sleeper closes its gap under load, which this does not represent.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from .track import (Ballast, Pad, Sleeper, Track, damped_stiffness, free_receptance, free_receptance_poles, lattice_factors, lattice_tails,
                    require_nonnegative, require_positive)

__all__ = ["Support", "RailDamper", "TrackCell", "RandomSupports", "make_cell", "point_stiffness", "cell_lattice_sum", "cell_lattice_sums_excluding",
           "cell_stationary_receptance"]


@dataclass(frozen=True, slots=True)
class Support:
    """One support of a cell.

    position     : s_j, m from the cell's first support, in [0, P)
    pad          : Pad (stiffness N/m, loss factor, viscous damping N s/m)
    sleeper_mass : half-sleeper mass m_S, kg (>= 0)
    ballast      : Ballast under the half sleeper (stiffness N/m, loss factor, viscous damping N s/m)
    """

    position: float
    pad: Pad
    sleeper_mass: float
    ballast: Ballast

    def __post_init__(self):
        require_nonnegative("support.position", self.position)
        require_nonnegative("support.sleeper_mass", self.sleeper_mass)


@dataclass(frozen=True, slots=True)
class RailDamper:
    """A tuned rail damper: mass m_D on a spring k_D fixed to the rail at ``position``.

    position        : m from the cell's first support, in [0, P)
    mass            : m_D, kg (> 0)
    stiffness       : k_D, N/m (> 0)
    loss_factor     : eta_D, - (>= 0, hysteretic model)
    viscous_damping : c_D, N s/m (>= 0, viscous model)

    Its dynamic stiffness seen by the rail is K_D = k_D (-m_D omega^2) / (k_D - m_D omega^2): a
    support with no ballast (k_B = 0).  Tuned to f_D = sqrt(k_D / m_D) / 2 pi.
    """

    position: float
    mass: float
    stiffness: float
    loss_factor: float = 0.0
    viscous_damping: float = 0.0

    def __post_init__(self):
        require_nonnegative("damper.position", self.position)
        require_positive("damper.mass", self.mass)
        require_positive("damper.stiffness", self.stiffness)
        require_nonnegative("damper.loss_factor", self.loss_factor)
        require_nonnegative("damper.viscous_damping", self.viscous_damping)


@dataclass(frozen=True)
class TrackCell:
    """A track periodic over a cell of length P with N supports (and optional rail dampers).

    Attributes
    ----------
    track : Track: the rail, the damping model ('hysteretic' or 'viscous') and the nominal
               support, whose spacing is the cell's mean spacing P / N
    supports : tuple of Support, positions strictly increasing, the first at 0, the last < P
    period : P, m (> 0)
    dampers : tuple of RailDamper (positions in [0, P))
    """

    track: Track
    supports: tuple
    period: float
    dampers: tuple = ()

    def __post_init__(self):
        require_positive("track.cell.period", self.period)
        if len(self.supports) < 1:
            raise ValueError("track.cell.supports is empty: a cell needs at least one support.")
        pos = np.array([s.position for s in self.supports], dtype=float)
        if pos[0] != 0.0:
            raise ValueError(f"track.cell: the first support must sit at 0 m (the cell's origin); it is at {pos[0]!r} m.")
        if np.any(np.diff(pos) <= 0):
            raise ValueError(f"track.cell: support positions {pos.tolist()} m must be strictly increasing.")
        if not pos[-1] < self.period:
            raise ValueError(f"track.cell: the last support at {pos[-1]!r} m must lie before the period P = {self.period!r} m.")
        for d in self.dampers:
            if not 0.0 <= d.position < self.period:
                raise ValueError(f"track.cell: a rail damper at {d.position!r} m lies outside the cell [0, {self.period!r}) m.")
        if not np.isclose(self.track.L * len(self.supports), self.period, rtol=1e-12, atol=0.0):
            raise ValueError(f"track.cell: the nominal track's spacing {self.track.L!r} m must be the mean spacing "
                             f"P / N = {self.period / len(self.supports)!r} m.")

    @staticmethod
    def uniform(track: Track, bays: int = 1) -> "TrackCell":
        """The uniform track of rail.track over ``bays`` bays: identical supports at spacing L.

        Parameters
        ----------
        track : Track
        bays : int
            N [-], >= 1.

        Returns
        -------
        TrackCell
        """
        if int(bays) != bays or bays < 1:
            raise ValueError(f"bays = {bays!r} is not allowed: it must be an integer >= 1.")
        L = track.L
        s = tuple(Support(j * L, track.pad, track.sleeper.mass, track.ballast) for j in range(int(bays)))
        return TrackCell(track, s, int(bays) * L)

    @property
    def bays(self) -> int:
        """N, the number of supports (bays) in the cell [-]."""
        return len(self.supports)

    @property
    def mean_spacing(self) -> float:
        """P / N [m]."""
        return self.period / self.bays

    @property
    def beta_p(self) -> float:
        """Cell wavenumber 2 pi / P [rad/m]."""
        return 2 * np.pi / self.period

    @property
    def positions(self) -> np.ndarray:
        """Positions of every point attachment [m]: the supports, then the dampers."""
        return np.array([s.position for s in self.supports] + [d.position for d in self.dampers], dtype=float)

    @property
    def is_uniform(self) -> bool:
        """True if every support equals the nominal one at equal spacing and there is no damper."""
        tr = self.track
        L = self.mean_spacing
        return (not self.dampers) and all(
            s.pad == tr.pad and s.ballast == tr.ballast and s.sleeper_mass == tr.sleeper.mass and np.isclose(s.position, j * L, rtol=0, atol=1e-12)
            for j, s in enumerate(self.supports))

    def support_track(self, j: int) -> Track:
        """The uniform Track with support j's pad, sleeper mass and ballast (spacing: the mean)."""
        s = self.supports[j]
        return dataclasses.replace(self.track, pad=s.pad, ballast=s.ballast, sleeper=Sleeper(s.sleeper_mass, self.mean_spacing))


def point_stiffness(cell: TrackCell, omega) -> np.ndarray:
    """Dynamic stiffness K_j(omega) of every point attachment of the cell (supports, then dampers).

    Support: pad k_P in series with the sleeper mass on the ballast (rail.track.support_stiffness),
    K = k_P (k_B - m_S omega^2) / (k_P + k_B - m_S omega^2); damper: the same with k_B = 0.

    Parameters
    ----------
    cell : TrackCell
    omega : float or ndarray
        Angular frequency [rad/s].

    Returns
    -------
    complex ndarray, shape omega.shape + (points,)
        K_j [N/m].
    """
    omega = np.asarray(omega, dtype=float)
    model = cell.track.damping
    out = []
    for s in cell.supports:
        kp = damped_stiffness(s.pad.stiffness, s.pad.loss_factor, s.pad.viscous_damping, omega, model)
        kbm = damped_stiffness(s.ballast.stiffness, s.ballast.loss_factor, s.ballast.viscous_damping, omega, model) - s.sleeper_mass * omega**2
        out.append(kp * kbm / (kp + kbm))
    for d in cell.dampers:
        kd = damped_stiffness(d.stiffness, d.loss_factor, d.viscous_damping, omega, model)
        m = -d.mass * omega**2
        out.append(kd * m / (kd + m))
    return np.stack(np.broadcast_arrays(*out), axis=-1)


def cell_lattice_sum(beta, omega, x: float, period: float, track: Track, poles=None):
    """Phased lattice sum over the cell, S_x(beta) = sum_m H(beta + m beta_P, omega) exp(i (beta + m beta_P) x).

    Closed form per partial fraction of H (docs/track.md, "Lattice sums in closed form", with L -> P):
    for 0 < x < P::

      sum_m e^{i q x} / (q - p) =  i P e^{i p x} / (1 - e^{i (p - beta) P}),
      sum_m e^{i q x} / (q + p) = -i P e^{i p (P - x)} e^{i beta P} / (1 - e^{i (p + beta) P}),

    q = beta + m beta_P; x = 0 is the unphased sum (the sum of H is continuous there), and
    S_{x - P} = e^{-i beta P} S_x gives -P < x < 0.

    Parameters
    ----------
    beta, omega : array_like
        Wavenumber [rad/m] and angular frequency [rad/s] (!= 0), broadcast together.
    x : float
        Phase distance [m], -P < x < P.
    period : float
        P [m].
    track : Track
        The rail (only its rail and damping model are used).
    poles : (c, p), optional
        The partial fractions H = sum_j c_j / (beta^2 - p_j^2) of another free receptance, c_j [1/N] and p_j
        [rad/m] with Im p_j >= 0, each broadcast with beta (the axial rod's, rail.creepage.rail_flexibility_cell); default the
        Timoshenko rail's (rail.track.free_receptance_poles).

    Returns
    -------
    complex ndarray
        S_x [m^2/N], broadcast shape of beta and omega.
    """
    beta, omega = np.broadcast_arrays(np.asarray(beta, dtype=float), np.asarray(omega, dtype=float))
    P = float(period)
    if not -P < x < P:
        raise ValueError(f"x = {x!r} m must lie in (-P, P) = ({-P}, {P}) m.")
    c, p = free_receptance_poles(omega, track) if poles is None else poles
    eBP = np.exp(1j * beta * P)
    out = 0j
    xr = x + P if x < 0 else x
    for cj, pj in zip(c, p):
        if xr == 0.0:
            out = out + cj * (P / (2 * pj)) * lattice_factors(pj, beta, P)[0]
        else:
            t1 = 1j * P * np.exp(1j * pj * xr) / (1 - np.exp(1j * (pj - beta) * P))
            t2 = -1j * P * np.exp(1j * pj * (P - xr)) * eBP / (1 - np.exp(1j * (pj + beta) * P))
            out = out + cj / (2 * pj) * (t1 - t2)
    if x < 0:
        out = out / eBP
    return out


def _static_free(q, omega, track: Track):
    """Quasi-static free receptance 1/(EI q^4) + 1/(kappa G A q^2) with the complex stiffnesses at omega."""
    from .track import rail_stiffnesses

    EI, kGA = rail_stiffnesses(track, omega)
    return 1.0 / (EI * q**4) + 1.0 / (kGA * q**2)


def cell_lattice_sums_excluding(beta, omega, xs, period: float, track: Track, explicit: int = 40, tail: int = 4000):
    """sum over m != 0 of H(beta + m beta_P, omega) exp(i (beta + m beta_P) x) for every x in ``xs``.

    For wavenumbers near the static point (beta, omega -> 0), where H(beta) ~ 1/(EI beta^4) diverges
    and the closed form would lose every digit to the cancellation with the m = 0 term.  Explicit
    summation: H itself for 0 < abs(m) <= ``explicit``, then its quasi-static form 1/(EI q^4) +
    1/(kappa G A q^2): for x = 0 the whole rest in closed form by polygamma (as the uniform track
    always did), for x != 0 explicitly to abs(m) = ``tail`` (the terms fall like 1/(kappa G A m^2 beta_P^2)
    and turn in phase with m, so the truncation error is O(1/tail^2)).

    Parameters
    ----------
    beta, omega : ndarray, 1-D, same length
        Wavenumbers [rad/m] and angular frequencies [rad/s].
    xs : array_like, 1-D
        Phase distances [m], -P < x < P.
    period : float
        P [m].
    track : Track

    Returns
    -------
    complex ndarray, shape (len(beta), len(xs))
    """
    from .track import rail_stiffnesses

    beta = np.asarray(beta, dtype=float)
    omega = np.asarray(omega, dtype=float)
    xs = np.asarray(xs, dtype=float)
    bP = 2 * np.pi / period
    out = np.zeros((len(beta), len(xs)), dtype=complex)
    m1 = np.concatenate([np.arange(-explicit, 0), np.arange(1, explicit + 1)])
    q1 = beta[:, None] + m1[None, :] * bP
    H1 = free_receptance(q1, omega[:, None], track)
    out += H1 @ np.exp(1j * np.outer(m1 * bP, xs))
    zero = xs == 0
    if (~zero).any():  # phased: the quasi-static terms explicitly to |m| = tail
        m2 = np.concatenate([np.arange(-tail, -explicit), np.arange(explicit + 1, tail + 1)])
        q2 = beta[:, None] + m2[None, :] * bP
        H2 = _static_free(q2, omega[:, None], track)
        out[:, ~zero] += H2 @ np.exp(1j * np.outer(m2 * bP, xs[~zero]))
    out *= np.exp(1j * np.outer(beta, xs))
    if zero.any():  # unphased: the quasi-static rest |m| > explicit in closed form (polygamma)
        EI, kGA = rail_stiffnesses(track, omega)
        _, s2, _, s4 = lattice_tails(beta, bP, explicit)
        out[:, zero] += (s4 / EI + s2 / kGA)[:, None]
    return out


def _differences(cell: TrackCell):
    """Distinct phase distances s_j - s_l of the attachments and the index map (l, j) -> distance."""
    s = cell.positions
    d = np.round(s[None, :] - s[:, None], 12)  # d[l, j] = s_j - s_l
    xs, inv = np.unique(d, return_inverse=True)
    return xs, inv.reshape(d.shape)


def cell_sum_matrix(beta, omega, cell: TrackCell, exclude_zero: bool = False):
    """Matrix of phased lattice sums S[l, j] = S_{s_j - s_l}(beta, omega) over the cell's attachments.

    Parameters
    ----------
    beta, omega : ndarray, 1-D, same length
    cell : TrackCell
    exclude_zero : bool
        Leave out the m = 0 term H(beta) exp(i beta (s_j - s_l)) (cell_lattice_sums_excluding).

    Returns
    -------
    complex ndarray, shape (len(beta), points, points) [m^2/N]
    """
    xs, idx = _differences(cell)
    if exclude_zero:
        vals = cell_lattice_sums_excluding(beta, omega, xs, cell.period, cell.track)
    else:
        vals = np.stack([cell_lattice_sum(beta, omega, float(x), cell.period, cell.track) for x in xs], axis=-1)
    return vals[:, idx]


def cell_stationary_receptance(x, x0, omega, cell: TrackCell, rtol: float = 1e-7, return_error=False):
    """Receptance alpha(x, x0; omega) of the rail on the cell's supports under a harmonic point force.

    Force F e^{i omega t} at x0; the attachments react with R_{j,m} = K_j w(s_j + m P).  A discrete
    Fourier transform over the cells (Floquet wavenumber kappa in the cell's Brillouin zone
    abs(kappa) <= beta_P / 2) gives, for each kappa, N equations for the reactions
    (docs/track.md, "A cell of N bays")::

        (I + diag(K) S(kappa) / P) R = diag(K) s_{x0}(kappa) / P,   S[l, j] = S_{s_j - s_l}(kappa),
                                                                    s_{x0}[l] = S_{x0 - s_l}(kappa),
        alpha = G(x - x0) - (1 / 2 pi) int_BZ sum_j S_{x - s_j}(-kappa) R_j(kappa) d kappa   (unit force)

    with G the free-rail Green's function.  For one support this is rail.track.stationary_receptance.

    Parameters
    ----------
    x, x0 : float or array_like
        Response and force positions [m] (any real), broadcast together: one receptance per pair,
        all from one adaptive zone quadrature.
    omega : float
        Angular frequency [rad/s], a finite scalar != 0.
    cell : TrackCell
    rtol : float
        Relative tolerance of the adaptive zone quadrature [-].
    return_error : bool
        Also return the estimated absolute quadrature error [m/N].

    Returns
    -------
    complex or complex ndarray (and its error with return_error)
        alpha [m/N], the broadcast shape of x and x0.
    """
    from .quadrature import adaptive_panels
    from .track import free_green

    if np.ndim(omega) != 0 or not (np.isfinite(omega) and omega != 0):
        raise ValueError(f"omega = {omega!r} rad/s is not allowed: it must be a finite scalar != 0.")
    xb, x0b = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(x0, dtype=float))
    xs, x0s = xb.ravel(), x0b.ravel()
    P = cell.period
    s = cell.positions
    n = len(s)
    Kj = point_stiffness(cell, omega)  # (n,)

    def phased(kap, dist):
        # S_dist(kap) for any real dist: reduce into [0, P) with S_{d + P} = e^{i kap P} S_d
        j = np.floor(dist / P)
        r = dist - j * P
        return cell_lattice_sum(kap, omega, float(r), P, cell.track) * np.exp(1j * kap * P * j)

    def integrand(kap):
        om = np.full(kap.shape, float(omega))
        S = cell_sum_matrix(kap, om, cell)  # (nk, n, n)
        rhs = np.stack([np.stack([phased(kap, a0 - sl) for sl in s], axis=-1) for a0 in x0s], axis=-1) * Kj[None, :, None] / P
        Mx = np.eye(n)[None] + Kj[None, :, None] * S / P
        R = np.linalg.solve(Mx, rhs)  # (nk, n, pairs)
        obs = np.stack([np.stack([phased(-kap, a - sj) for sj in s], axis=-1) for a in xs], axis=-1)
        return np.sum(obs * R, axis=1)

    bP = 2 * np.pi / P
    q = adaptive_panels(integrand, np.linspace(-bP / 2, bP / 2, 9), rtol=rtol)
    alpha = (free_green(xs - x0s, omega, cell.track) - q.integral / (2 * np.pi)).reshape(xb.shape)
    err = (q.error / (2 * np.pi)).reshape(xb.shape)
    if alpha.ndim == 0:
        alpha, err = complex(alpha), float(err)
    return (alpha, err) if return_error else alpha


@dataclass(frozen=True)
class RandomSupports:
    """Seeded random factors on the supports of a cell (a random track).

    The draws are taken in a fixed order (spacing, pad, ballast, sleeper mass; N each), whatever the
    spreads, so that a seed gives the same track bit for bit and a spread of 0 leaves the others'
    draws unchanged.

    Attributes
    ----------
    seed : seed of numpy.random.default_rng [-]
    distribution : 'uniform' (factor 1 + s u, u uniform in [-1, 1]) or 'normal' (1 + s g, g standard
                   normal cut at +-3)
    spacing, pad, ballast, sleeper_mass : spreads s [-] in [0, 0.3]
    """

    seed: int
    distribution: str = "uniform"
    spacing: float = 0.0
    pad: float = 0.0
    ballast: float = 0.0
    sleeper_mass: float = 0.0

    def __post_init__(self):
        if int(self.seed) != self.seed or self.seed < 0:
            raise ValueError(f"track.cell.random.seed = {self.seed!r} is not allowed: it must be an integer >= 0.")
        if self.distribution not in ("uniform", "normal"):
            raise ValueError(f"track.cell.random.distribution = {self.distribution!r} is not allowed: it must be 'uniform' or 'normal'.")
        for name in ("spacing", "pad", "ballast", "sleeper_mass"):
            v = getattr(self, name)
            if not (np.isfinite(v) and 0.0 <= v <= 0.3):
                raise ValueError(f"track.cell.random.{name} = {v!r} is not allowed: the spread must lie in [0, 0.3].")

    def factors(self, bays: int) -> dict:
        """The drawn factors {'spacing', 'pad', 'ballast', 'sleeper_mass'}: arrays of N [-]."""
        rng = np.random.default_rng(int(self.seed))
        out = {}
        for name in ("spacing", "pad", "ballast", "sleeper_mass"):
            if self.distribution == "uniform":
                u = rng.uniform(-1.0, 1.0, bays)
            else:
                u = np.clip(rng.standard_normal(bays), -3.0, 3.0)
            out[name] = 1.0 + getattr(self, name) * u
        return out


def make_cell(track: Track, bays: int, spacing=None, pad=None, ballast=None, sleeper_mass=None,
              damper: dict | None = None, random: RandomSupports | None = None) -> TrackCell:
    """A cell of N bays from the nominal track and per-support factors.

    Parameters
    ----------
    track : Track
        The nominal track (rail, damping model, nominal pad, sleeper, ballast).
    bays : int
        N [-], >= 1.
    spacing : sequence of N float, optional
        Bay lengths [m]; support j + 1 sits spacing[j] after support j (default: the nominal spacing).
    pad, ballast, sleeper_mass : sequence of N float, optional
        Factors [-] (> 0) on each support's pad stiffness and dashpot, ballast stiffness and dashpot,
        and half-sleeper mass; loss factors stay (default 1).
    damper : dict, optional
        A rail damper in every bay: mass [kg], frequency [Hz] (tuning sqrt(k/m) / 2 pi), loss_factor
        [-], viscous_damping [N s/m], position [-] as a fraction of the bay after its support; every
        key given (rail.setup.build.track_cell fills the schema's defaults of the optional ones).
    random : RandomSupports, optional
        Random factors multiplying the given ones; the random bay lengths are rescaled so that the
        period keeps the length of the given ones.

    Returns
    -------
    TrackCell
        With the nominal track's spacing set to the mean P / N.
    """
    if int(bays) != bays or bays < 1:
        raise ValueError(f"track.cell.bays = {bays!r} is not allowed: it must be an integer >= 1.")
    N = int(bays)

    def arr(name, v, default):
        if v is None:
            return np.full(N, float(default))
        a = np.asarray(v, dtype=float)
        if a.shape != (N,):
            raise ValueError(f"track.cell.{name} has {a.size} values: it needs one per bay, N = {N}.")
        if not np.all(np.isfinite(a) & (a > 0)):
            raise ValueError(f"track.cell.{name} = {a.tolist()} is not allowed: every value must be a finite number > 0.")
        return a

    sp = arr("spacing", spacing, track.L)
    fp, fb, fm = arr("pad", pad, 1.0), arr("ballast", ballast, 1.0), arr("sleeper_mass", sleeper_mass, 1.0)
    if random is not None:
        r = random.factors(N)
        period = sp.sum()
        sp = sp * r["spacing"]
        sp = sp * (period / sp.sum())
        fp, fb, fm = fp * r["pad"], fb * r["ballast"], fm * r["sleeper_mass"]
    period = float(sp.sum())
    pos = np.concatenate([[0.0], np.cumsum(sp)[:-1]])
    nominal = dataclasses.replace(track, sleeper=Sleeper(track.sleeper.mass, period / N))
    supports = tuple(
        Support(float(pos[j]), Pad(track.pad.stiffness * fp[j], track.pad.loss_factor, track.pad.viscous_damping * fp[j]),
                track.sleeper.mass * fm[j],
                Ballast(track.ballast.stiffness * fb[j], track.ballast.loss_factor, track.ballast.viscous_damping * fb[j]))
        for j in range(N))
    dampers = ()
    if damper is not None:
        m = float(damper["mass"])
        f = float(damper["frequency"])
        frac = float(damper["position"])
        if not 0.0 <= frac < 1.0:
            raise ValueError(f"track.cell.damper.position = {frac!r} is not allowed: it must lie in [0, 1) (a fraction of the bay).")
        dampers = tuple(RailDamper(float(pos[j] + frac * sp[j]), m, m * (2 * np.pi * f) ** 2, float(damper["loss_factor"]),
                                   float(damper["viscous_damping"])) for j in range(N))
    return TrackCell(nominal, supports, period, dampers)
