"""The wheels' roughness as a source of rail roughness, and the level each line settles to (issue 58).

A wheel's roughness passes through the contact as the rail's does: the normal force and the patch see
the combined roughness r_rail + r_wheel, both carried through the patch at the speed V (in the rail's
frame and in the wheel's). A passage over a rail line Z_j with a wheel roughness W_j at the same
wavenumber changes the rail's line by -R_own (Z_j + W_j) per wheel, R_own the wheel's own transfer (the
rate of the growth-rate spectrum, rail.growth_spectrum.rate_spectrum, of that wheel alone). The wheel's
phase relative to the rail differs from passage to passage (a wheel's circumference is not
commensurate with the track, and each train brings other wheels): E[W_j] = 0 and, independent of the
rail's roughness, E[2 abs(W_j)^2] = P_j, the wheel's mean square on the line. The rail's expected
mean square on the line, S = E[2 abs(Z_j)^2], then obeys per train passage

    S_{n+1} = a S_n + Q,   a = abs(1 - R)^2,   Q = sum over the wheels of abs(R_own)^2 P_j,

R the train's rate (the spectrum's, the roughness grows like exp(-R n)). With g = -Re R (the growth
rate per train passage) a = 1 + 2 g + abs(R)^2, and for small rates dS/dn = 2 g S + Q, the issue's
equation. Its solution from S_0 is S_n = a^n S_0 + Q (1 - a^n) / (1 - a); where a < 1 (the line decays)
S settles at S_inf = Q / (1 - a) = Q / (-2 g - abs(R)^2), highest where the damping is least. The
supports' parametric source (the smooth rail's wear at the comb lines, ``source`` of the spectrum, an
amplitude s per train passage) adds a coherent part: its amplitude c_{n+1} = (1 - R) c_n + s from 0,
so c_n = s (1 - (1 - R)^n) / R, and its mean square abs(c_n)^2 / 2 adds to S (the rail's roughness and
the wheels' have random phases against it).

The wheel's line power from a one-third-octave spectrum: each band's mean square spread evenly over
the band's wavenumbers (the density constant in k across the band; the band edges of rail.bands), so a
line 2 pi / (N L) wide in k holds the share (1 / (N L)) / (1 / lambda_lower - 1 / lambda_upper) of its
band's mean square, and the lines of a period inside a band sum to the band. A band's expected level
back from the lines: the mean over the spectrum's lines inside the band of S_j / share_j (the lines
sample the band's density; with the band's lines 15 Hz apart near pinned-pinned, about 15 lines
per band there, 1-2 on the log-spaced lines elsewhere), plus the coherent comb lines' own mean squares.

Under a fleet (rail.fleet: each passage one train drawn from the classes c, a vehicle at a speed, with
probability w_c, independently from passage to passage and of the wheels' phases), the class of a
passage multiplies the rail's line by (1 - R_c) and adds its wheels' increment. Conditioned on the
classes drawn, the wheels' increments keep a zero mean and their own mean squares; averaged over the
draw, the expected mean square obeys per fleet passage

    S_{n+1} = a S_n + Q,   a = sum_c w_c abs(1 - R_c)^2,   Q = sum_c w_c Q_c,

R_c the class train's rate per passage of that train and Q_c its wheels' source per passage of that
train, as for one train (fleet_decay_factor, fleet_source_power). With R = sum_c w_c R_c (the fleet's
rate, rail.growth_spectrum.combine_spectra) a = abs(1 - R)^2 + sum_c w_c abs(R_c - R)^2: the draw of the
class retains more than the mean train does. The closed form and settled level are those above with this
a (the ``decay`` argument). A fleet passage is one train; per axle passage divide by the fleet's mean
axles per train (rail.fleet.Fleet.axles_per_train), as the fleet's spectrum does.

The supports' comb under a fleet (fleet_comb_mean_square): each class adds its source s_c coherently,
c_{n+1} = (1 - R_c) c_n + s_c with the class drawn. The classes' sources are taken in phase (the
spectrum keeps their magnitudes only; combine_spectra sums them with the weights, an upper bound).
The comb's mean amplitude m_n = E c_n follows the fleet's rate and source, m_{n+1} = (1 - R) m_n + s,
s = sum_c w_c s_c: the one-train comb of the fleet's spectrum. The draw adds a spread about it,
V_n = E abs(c_n - m_n)^2, with V_{n+1} = a V_n + sum_c w_c abs((R_c - R) m_n - (s_c - s))^2 from V_0 = 0,
and the comb's mean square is (abs(m_n)^2 + V_n) / 2. For one class V = 0 and it is the one-train comb.
The spread is of order abs(R) of the mean comb (its settled part sum_c w_c abs((R_c - R) s / R - (s_c -
s))^2 / (1 - a) against abs(s / R)^2). At a locked line each class's rate is its own (the slower-decaying
of its pair) and the mean comb the fleet's (the eigenvalue of the weighted operators).

Range and what is left out:

* Each wheel's own transfer is taken from the wheel alone on the track (rail.chain.single_wheel): a
  wheel's roughness excites the track under the other wheels of its train too, and they wear the
  rail by it; those cross terms are left out for a train of several wheels (exact for one wheel,
  where R_own = R).
* At a locked line (a wavelength locked to the supports: the cosine and sine about the supports
  grow at two rates) the source and the decay are taken with the line's rate R (the slower-decaying
  of the pair): a bound from above on the settled level there.
* A sideband of the supports (the wheel's roughness at j feeding the rail at j +- N) carries the
  share ``sideband`` of the spectrum (its largest sideband over the line itself): left out of Q.
* Linear: every line small against the amplitude at which the contact's response stops being linear
  (the spectrum's linearity check); a wheel roughness far above the rail's keeps the linearisation
  about the smooth rail where the force stays far from contact loss.
"""

from __future__ import annotations

import numpy as np

from ..bands import in_band, third_octave_edges

__all__ = ["line_share", "wheel_line_power", "source_power", "axle_source_power", "expected_mean_square", "settled_mean_square",
           "passages_to_settle", "band_mean_square_from_lines", "passages_to_limit", "fleet_decay_factor", "fleet_source_power",
           "fleet_comb_mean_square", "fleet_settled_comb"]


def line_share(wavelength, period: float, centres):
    """The share of a one-third-octave band's mean square that one line of the period holds (the
    band's density constant in wavenumber; module docstring), and the band each line lies in.

    Parameters
    ----------
    wavelength : array_like
        The lines' wavelengths N L / j [m].
    period : float
        N L, the period the lines belong to [m].
    centres : array_like
        The bands' centre wavelengths [m] (rail.bands.third_octave_edges gives their edges).

    Returns
    -------
    share : ndarray
        (1 / period) / (1 / lower - 1 / upper) of the line's band [-]; NaN where no band holds the line.
    band : ndarray of int
        The index in ``centres`` of each line's band [-]; -1 where none holds it.
    """
    lam = np.atleast_1d(np.asarray(wavelength, dtype=float))
    if not (np.isfinite(period) and period > 0):
        raise ValueError(f"period = {period!r} is not allowed: the lines' period N L must be a finite length > 0 m.")
    lo, hi = third_octave_edges(np.asarray(centres, dtype=float))
    band = np.full(lam.shape, -1, dtype=int)
    for b in range(lo.size):
        band[in_band(lam, lo[b], hi[b]) & (band < 0)] = b
    share = np.full(lam.shape, np.nan)
    ok = band >= 0
    share[ok] = (1.0 / period) / (1.0 / lo[band[ok]] - 1.0 / hi[band[ok]])
    return share, band


def wheel_line_power(wavelength, period: float, centres, level_dB):
    """P_j: the wheel roughness's mean square on each line of the period [m^2] (E[2 abs(W_j)^2]), from
    its one-third-octave spectrum (line_share).

    Parameters
    ----------
    wavelength : array_like
        The lines' wavelengths [m].
    period : float
        N L [m].
    centres : array_like
        The spectrum's band centre wavelengths [m].
    level_dB : array_like
        Its band levels [dB re 1 µm rms], finite.

    Returns
    -------
    ndarray
        [m^2]; NaN on a line outside the spectrum's bands.
    """
    lev = np.asarray(level_dB, dtype=float)
    if lev.shape != np.shape(centres) or not np.all(np.isfinite(lev)):
        raise ValueError(f"level_dB: a wheel roughness spectrum needs one finite level per band ({np.size(centres)} bands), "
                         f"got {lev.tolist()}.")
    share, band = line_share(wavelength, period, centres)
    ms = np.where(band >= 0, 1e-12 * 10.0 ** (lev[np.maximum(band, 0)] / 10), np.nan)
    return ms * share


def source_power(rate_own, power, wheels: int):
    """Q_j: the expected mean square the wheels' roughness adds to the rail's line per train passage
    [m^2], sum over the wheels of abs(R_own)^2 P_j (identical wheels, each with its own random phase).

    Parameters
    ----------
    rate_own : array_like, complex
        R_own, one wheel's own rate per passage of that wheel [-] (the single wheel's spectrum).
    power : array_like
        P_j [m^2] (wheel_line_power).
    wheels : int
        Wheels of the train [-].

    Returns
    -------
    ndarray
        [m^2 per train passage].
    """
    if int(wheels) != wheels or wheels < 1:
        raise ValueError(f"wheels = {wheels!r} is not allowed: a train has a whole number >= 1 of wheels.")
    return int(wheels) * np.abs(np.asarray(rate_own)) ** 2 * np.asarray(power, dtype=float)


def axle_source_power(rate_own, power):
    """Q_j of a train whose wheels differ (a fleet vehicle's axles: each its own creepage and wheelset), sum over
    the wheels l of abs(R_own,l)^2 P_j [m^2 per train passage] (each wheel with its own random phase).

    Parameters
    ----------
    rate_own : array_like, complex, (wheels, ...)
        Each wheel's own rate per passage of that wheel [-] (the wheel alone on the track).
    power : array_like, (...)
        P_j [m^2] (wheel_line_power; the vehicle's wheels share one roughness).

    Returns
    -------
    ndarray, (...)
        [m^2 per train passage].
    """
    own = np.asarray(rate_own)
    if own.ndim < 1 or own.shape[0] < 1:
        raise ValueError(f"rate_own: give one row of rates per wheel (shape (wheels, lines)), got shape {own.shape}.")
    return np.sum(np.abs(own) ** 2, axis=0) * np.asarray(power, dtype=float)


def _decay_factor(rate):
    """a = abs(1 - R)^2 [-]."""
    return np.abs(1.0 - np.asarray(rate, dtype=complex)) ** 2


def _comb_mean_square(n, R, s):
    """abs(c_n)^2 / 2 of the coherent comb c_{n+1} = (1 - R) c_n + s from c_0 = 0 [m^2] (n, R, s broadcast)."""
    gain = np.where(np.abs(R) > 0, (1 - (1 - R) ** n) / np.where(R == 0, 1, R), n)
    return np.where(s != 0, np.abs(s * gain) ** 2 / 2, 0.0)


def expected_mean_square(n, start, rate, Q, comb=None, decay=None):
    """S_n: the rail line's expected mean square after n train passages [m^2] (module docstring),
    S_n = a^n S_0 + Q (1 - a^n) / (1 - a) plus the supports' coherent part abs(c_n)^2 / 2.

    Parameters
    ----------
    n : array_like
        Train passages [-], >= 0 (broadcast against the lines).
    start : array_like
        S_0 [m^2].
    rate : array_like, complex
        R per train passage [-].
    Q : array_like
        [m^2 per train passage].
    comb : array_like, optional
        s, the supports' source amplitude per train passage [m] (the spectrum's ``source``; 0 off the comb).
    decay : array_like, optional
        a per passage [-] of the random part (default abs(1 - R)^2, one train; a fleet's fleet_decay_factor
        per fleet passage, its comb then fleet_comb_mean_square).

    Returns
    -------
    ndarray
        [m^2].
    """
    n = np.asarray(n, dtype=float)
    R = np.asarray(rate, dtype=complex)
    a = _decay_factor(R) if decay is None else np.asarray(decay, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):  # a growing line overflows to inf, as it should
        an = a ** n
        # (1 - a^n) / (1 - a) = n at a = 1, and within rounding of it where 1 - a is below 1e-12
        frac = np.where(np.abs(1 - a) > 1e-12, (1 - an) / (1 - a), n)
        S0, Qa = np.asarray(start, dtype=float), np.asarray(Q, dtype=float)
        S = np.where(S0 != 0, an * S0, 0.0) + np.where(Qa != 0, Qa * frac, 0.0)  # a zero start or source adds nothing
        if comb is not None:
            S = S + _comb_mean_square(n, R, np.asarray(comb, dtype=float))
    return S


def settled_mean_square(rate, Q, comb=None, decay=None):
    """S_inf: the level a decaying line settles to [m^2], Q / (1 - a) plus (abs(s / R)^2) / 2 from the
    supports; inf where the line does not decay (a >= 1: it grows, or it holds).

    Parameters
    ----------
    rate : array_like, complex
        R per train passage [-].
    Q : array_like
        [m^2 per train passage].
    comb : array_like, optional
        s [m per train passage].
    decay : array_like, optional
        a [-] (default abs(1 - R)^2; a fleet's fleet_decay_factor, its comb then fleet_settled_comb).

    Returns
    -------
    ndarray
        [m^2]; inf where a >= 1.
    """
    R = np.asarray(rate, dtype=complex)
    a = _decay_factor(R) if decay is None else np.asarray(decay, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        S = np.where(a < 1, np.asarray(Q, dtype=float) / (1 - a), np.inf)
        if comb is not None:
            s = np.asarray(comb, dtype=float)
            S = S + np.where(a < 1, np.abs(s / np.where(R == 0, 1, R)) ** 2 / 2, np.where(s > 0, np.inf, 0.0))
    return S


def passages_to_settle(rate, within_dB: float = 1.0, decay=None):
    """Train passages for a line from a ground (zero) start to come within ``within_dB`` of its settled
    level under its wheels' source: 1 - a^n = 10^(-within_dB / 10), n = ln(1 - 10^(-within/10)) / ln a.

    Parameters
    ----------
    rate : array_like, complex
        R per train passage [-].
    within_dB : float
        [dB], > 0.
    decay : array_like, optional
        a [-] (default abs(1 - R)^2; a fleet's fleet_decay_factor, the passages then fleet passages).

    Returns
    -------
    ndarray
        [train passages]; inf where the line does not decay.
    """
    if not (np.isfinite(within_dB) and within_dB > 0):
        raise ValueError(f"within_dB = {within_dB!r} is not allowed: it must be a finite level > 0 dB.")
    a = _decay_factor(rate) if decay is None else np.asarray(decay, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(a < 1, np.log1p(-10 ** (-within_dB / 10)) / np.log(np.where(a < 1, a, 0.5)), np.inf)


def band_mean_square_from_lines(S, share, band, bands: int, coherent=None):
    """Band mean squares from the lines that sample them [m^2]: the mean of S_j / share_j over a band's
    lines (its density times its width), plus the coherent comb lines' own mean squares (module docstring).

    Parameters
    ----------
    S : ndarray, (..., lines)
        The lines' expected mean squares less their coherent part [m^2].
    share, band : ndarray, (lines,)
        line_share's [-].
    bands : int
        How many bands [-].
    coherent : ndarray, (..., lines), optional
        The coherent comb part of each line [m^2] (added as it is).

    Returns
    -------
    ndarray, (..., bands)
        [m^2]; NaN for a band no line samples.
    """
    S = np.asarray(S, dtype=float)
    out = np.full(S.shape[:-1] + (bands,), np.nan)
    for b in range(bands):
        sel = band == b
        if not sel.any():
            continue
        out[..., b] = np.mean(S[..., sel] / share[sel], axis=-1)
        if coherent is not None:
            out[..., b] += np.sum(np.asarray(coherent, dtype=float)[..., sel], axis=-1)
    return out


def passages_to_limit(band_ms, limit_ms, longest: float = 1e12, per_decade: int = 200):
    """The first train passage count at which a band's expected mean square exceeds its limit, per band.

    Parameters
    ----------
    band_ms : callable
        n (ndarray of passages) -> (len(n), bands) band mean squares [m^2] (expected_mean_square summed
        by band_mean_square_from_lines).
    limit_ms : ndarray, (bands,)
        [m^2]; NaN where a band has no limit.
    longest : float
        The most train passages looked at [-].
    per_decade : int
        Points per decade of the search grid 1 .. ``longest``, each crossing then bisected to 1e-6 of its
        passages [-].

    Returns
    -------
    ndarray, (bands,)
        [train passages]; 0 where a band starts above its limit; inf where it stays below up to ``longest``
        (or has no limit).
    """
    limit_ms = np.asarray(limit_ms, dtype=float)
    n = np.r_[0.0, np.logspace(0, np.log10(longest), int(per_decade * np.log10(longest)) + 1)]
    ms = band_ms(n)
    out = np.full(limit_ms.shape, np.inf)
    for b in range(limit_ms.size):
        if not np.isfinite(limit_ms[b]):
            continue
        over = np.nonzero(ms[:, b] > limit_ms[b])[0]
        if not over.size:
            continue
        i = int(over[0])
        if i == 0:
            out[b] = 0.0
            continue
        lo, hi = n[i - 1], n[i]
        while hi - lo > 1e-6 * hi:
            mid = 0.5 * (lo + hi)
            if band_ms(np.array([mid]))[0, b] > limit_ms[b]:
                hi = mid
            else:
                lo = mid
        out[b] = hi
    return out


def _class_arrays(rates, weights, name: str = "rates"):
    """The classes' rates (c, ...) as complex and their weights (c,) as float, checked against each other."""
    R = np.asarray(rates, dtype=complex)
    w = np.asarray(weights, dtype=float)
    if w.ndim != 1 or R.ndim < 1 or R.shape[0] != w.size or w.size < 1:
        raise ValueError(f"{name}: give one row per class ({w.size} weights), got shape {R.shape}.")
    if not np.all(np.isfinite(w)) or np.any(w < 0):
        raise ValueError(f"weights = {w.tolist()} is not allowed: each class's weight must be a finite number >= 0.")
    return R, w.reshape((-1,) + (1,) * (R.ndim - 1))


def fleet_decay_factor(rates, weights):
    """a = sum_c w_c abs(1 - R_c)^2 [-]: the share of the rail line's mean square a fleet passage keeps (module
    docstring), one train drawn from the classes c with probability w_c.

    Parameters
    ----------
    rates : array_like, complex, (classes, ...)
        R_c, each class's rate per passage of its train [-].
    weights : array_like, (classes,)
        w_c [-], summing to 1 (rail.fleet.FleetClass.weight).

    Returns
    -------
    ndarray, (...)
        [-]; for one class of weight 1 the one train's abs(1 - R)^2 exactly.
    """
    R, w = _class_arrays(rates, weights)
    return np.sum(w * _decay_factor(R), axis=0)


def fleet_source_power(Q, weights):
    """Q = sum_c w_c Q_c: the wheels' expected mean square added to the rail's line per fleet passage [m^2].

    Parameters
    ----------
    Q : array_like, (classes, ...)
        Q_c, each class's wheels' source per passage of its train [m^2] (source_power, axle_source_power).
    weights : array_like, (classes,)
        w_c [-].

    Returns
    -------
    ndarray, (...)
        [m^2 per fleet passage].
    """
    Qc, w = _class_arrays(Q, weights, "Q")
    if np.any(Qc.imag != 0):
        raise ValueError("Q: a mean square is real.")
    return np.sum(w * Qc.real, axis=0)


def _log1p_c(z):
    """log(1 + z) for complex z, accurate where abs(z) is small [-]."""
    x, y = z.real, z.imag
    return 0.5 * np.log1p(2 * x + x * x + y * y) + 1j * np.arctan2(y, 1 + x)


def _expm1_c(w):
    """exp(w) - 1 for complex w, accurate where abs(w) is small [-] (an imaginary part of 0 stays 0 on overflow)."""
    u, v = w.real, w.imag
    return np.expm1(u) * np.cos(v) - 2 * np.sin(v / 2) ** 2 + 1j * np.where(v == 0, 0.0, np.exp(u) * np.sin(v))


def _geometric_mix(n, alpha, kappa):
    """sum_{i=0}^{n-1} (1 + alpha)^(n-1-i) (1 + kappa)^i [-], by the ratio of the smaller factor to the larger
    (no overflow of the ratio's power; exp, expm1 and log1p keep it accurate where both factors are near 1)."""
    alpha = np.asarray(alpha, dtype=complex)
    kappa = np.asarray(kappa, dtype=complex)
    swap = np.abs(1 + kappa) > np.abs(1 + alpha)
    big = np.where(swap, kappa, alpha)
    rm1 = (np.where(swap, alpha, kappa) - big) / (1 + big)  # r - 1, r = small / big
    geo = np.where(rm1 == 0, n + 0j, _expm1_c(n * _log1p_c(rm1)) / np.where(rm1 == 0, 1, rm1))
    return (1 + _expm1_c((n - 1) * _log1p_c(big))) * geo


def _comb_spread(rates, sources, weights, mean_rate):
    """The fleet's mean comb (R, s, mu = s / R) and the spread's coefficients A, B, C of sum_c w_c abs(x_c - y_c b^i)^2,
    x_c = (R_c - R) mu - (s_c - s), y_c = (R_c - R) mu, b = 1 - R (module docstring)."""
    Rc, w = _class_arrays(rates, weights)
    sc = np.asarray(sources, dtype=float)
    if sc.shape != Rc.shape:
        raise ValueError(f"sources: give one row per class on the rates' lines, shape {Rc.shape}, got {sc.shape}.")
    R = np.sum(w * Rc, axis=0) if mean_rate is None else np.asarray(mean_rate, dtype=complex)
    s = np.sum(w * sc, axis=0)
    mu = np.where(R != 0, s / np.where(R == 0, 1, R), 0.0)
    y = (Rc - R) * mu
    x = y - (sc - s)
    A = np.sum(w * np.abs(x) ** 2, axis=0)
    B = np.sum(w * x * np.conj(y), axis=0)
    C = np.sum(w * np.abs(y) ** 2, axis=0)
    alpha = np.sum(w * (np.abs(Rc) ** 2 - 2 * Rc.real), axis=0)  # a - 1, without the rounding of a near 1
    return R, s, mu, A, B, C, alpha


def fleet_comb_mean_square(n, rates, sources, weights, mean_rate=None):
    """The supports' comb under a fleet: its expected mean square after n fleet passages from zero [m^2],
    (abs(m_n)^2 + V_n) / 2 (module docstring): the mean comb m_n of the fleet's rate and source, and the spread
    V_n = sum_{i<n} a^(n-1-i) sum_c w_c abs((R_c - R) m_i - (s_c - s))^2 that the draw of the class adds.

    Parameters
    ----------
    n : array_like
        Fleet passages [-], >= 0 (broadcast against the lines).
    rates : array_like, complex, (classes, lines)
        R_c per passage of the class's train [-].
    sources : array_like, (classes, lines)
        s_c, each class's comb source per passage of its train [m] (the spectrum's ``source``), taken in phase.
    weights : array_like, (classes,)
        w_c [-].
    mean_rate : array_like, complex, (lines,), optional
        R, the fleet's rate per fleet passage [-] (default sum_c w_c R_c; at a locked line the fleet spectrum's
        eigenvalue of the weighted operators).

    Returns
    -------
    ndarray
        [m^2]; for one class of weight 1 the one train's abs(c_n)^2 / 2 exactly; inf where the closed form
        overflows (a line that grows).
    """
    n = np.asarray(n, dtype=float)
    R, s, mu, A, B, C, alpha = _comb_spread(rates, sources, weights, mean_rate)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        mean = _comb_mean_square(n, R, s)
        bm1 = -R  # b - 1
        parts = [(A, _geometric_mix(n, alpha, 0.0)), (-2 * B, np.conj(_geometric_mix(n, np.conj(alpha), bm1))),
                 (C, _geometric_mix(n, alpha, np.abs(bm1) ** 2 - 2 * R.real))]
        V = sum(np.where(k != 0, (k * F).real, 0.0) for k, F in parts)
        V = np.where(np.isnan(V), np.inf, V)  # only an overflow of the closed form (a growing line) gives NaN here
    return mean + np.maximum(V, 0.0) / 2


def fleet_settled_comb(rates, sources, weights, mean_rate=None):
    """The level the supports' comb settles to under a fleet [m^2], (abs(s / R)^2 + A / (1 - a)) / 2 with
    A = sum_c w_c abs((R_c - R) s / R - (s_c - s))^2 (fleet_comb_mean_square's limit); inf where a >= 1 and the comb
    is not zero.

    Parameters
    ----------
    rates, sources, weights, mean_rate
        As fleet_comb_mean_square.

    Returns
    -------
    ndarray, (lines,)
        [m^2]; for one class the one train's abs(s / R)^2 / 2 exactly.
    """
    R, s, mu, A, B, C, alpha = _comb_spread(rates, sources, weights, mean_rate)
    a = fleet_decay_factor(rates, weights)
    with np.errstate(divide="ignore", invalid="ignore"):
        mean = np.abs(s / np.where(R == 0, 1, R)) ** 2 / 2
        spread = np.where(A != 0, A / (1 - np.where(a < 1, a, 0.0)) / 2, 0.0)
        return np.where(a < 1, mean + spread, np.where((s > 0) | (A > 0), np.inf, 0.0))
