"""The pads' rotational stiffness (track.pad.rotational_stiffness, issue 54): a moment spring k_theta on the
rail's bending rotation psi at every support, in the moving-load tables (rail.moving) and the head's tables
(rail.creepage.rail_flexibility).

Checked against
* the lattice sums' partial sums (rail.track.beam_lattice_sums),
* today's model: k_theta -> 0 gives the one-channel tables (the two-channel path, its static point included),
* a direct solution written without rail.moving and rail.creepage.rail_flexibility (tests/independent/rail_head_direct.py:
  the free rail's Green's functions by residues and 2 x 150 supports, each with a force and a moment reaction,
  solved for directly): the vertical receptance w/F and the head's psi/M, psi/F above a sleeper, at quarter-
  and at mid-span over 900-1,300 Hz, within 1 % (slow),
* an analytic limit: a stiff moment spring clamps the rail at the supports, so on rigid supports the mid-span
  resonance moves from the pinned-pinned frequency of the span (1,068 Hz) towards its clamped-clamped one
  (1,497 Hz: the Timoshenko span's frequency equation, written here).
"""

import dataclasses
import sys
from pathlib import Path

import numpy as np
import pytest

from rail.creepage import rail_flexibility as lg
from rail import moving
from rail.track import (MAX_ROTATIONAL_STIFFNESS, Ballast, Pad, Rail, Sleeper, Track, beam_lattice_sums, free_beam_receptances,
                        free_receptance, pinned_pinned_frequency, stationary_receptance, support_rotational_stiffness)

sys.path.insert(0, str(Path(__file__).parent / "independent"))
import rail_head_direct as direct  # noqa: E402

RAIL = Rail(2.1e11, 8.1e10, 7850.0, 7.69e-3, 3.055e-5, 0.4, 0.01, 1.6e-6)  # config/config.yaml
TRACK = Track(RAIL, Pad(3.5e8, 0.25, 2.8e4), Sleeper(162.0, 0.6), Ballast(5e7, 1.0, 8e4), "hysteretic")
# the schema's sourced value: k_P l^2 / 12 for the default pad 180 mm along the rail
K_THETA = 3.5e8 * 0.18**2 / 12


def with_k(track, k):
    return dataclasses.replace(track, pad=dataclasses.replace(track.pad, rotational_stiffness=k))


@pytest.mark.parametrize("bad", [-1.0, float("nan"), float("inf"), 2 * MAX_ROTATIONAL_STIFFNESS])
def test_a_bad_rotational_stiffness_is_refused_naming_its_key(bad):
    with pytest.raises(ValueError, match="track.pad.rotational_stiffness"):
        Pad(3.5e8, 0.25, 2.8e4, bad)


def test_the_moment_spring_is_damped_as_the_pad():
    om = np.array([-2 * np.pi * 1000.0, 2 * np.pi * 1000.0])
    k = support_rotational_stiffness(with_k(TRACK, K_THETA), om)
    assert np.allclose(k, K_THETA * (1 + 0.25j * np.sign(om)), rtol=1e-15)
    v = dataclasses.replace(with_k(TRACK, K_THETA), damping="viscous")
    assert np.allclose(support_rotational_stiffness(v, om), K_THETA + 1j * om * 2.8e4 * K_THETA / 3.5e8, rtol=1e-15)


def test_the_two_copies_of_the_free_beam_matrix_agree_and_invert_the_dynamic_stiffness():
    """rail.track.free_beam_receptances (rail.moving's) and rail.creepage.rail_flexibility.free_beam_matrix (the head's) are the
    same matrix, its w/F is rail.track.free_receptance, and it inverts the beam's dynamic stiffness D."""
    b = np.array([0.5, 3.0, -12.0, 40.0])
    om = 2 * np.pi * np.array([300.0, 1100.0, -900.0, 2000.0])
    H = free_beam_receptances(b, om, TRACK)
    G = lg.free_beam_matrix(b, om, TRACK)
    for k in range(4):
        assert np.allclose(H[k], G[k], rtol=1e-14, atol=0), k
    assert np.allclose(H[0], free_receptance(b, om, TRACK), rtol=1e-13, atol=0)
    r = TRACK.rail
    f = 1 + 1j * r.loss_factor * np.sign(om)
    EI, kGA = r.youngs_modulus * r.second_moment_of_area * f, r.shear_coefficient * r.shear_modulus * r.area * f
    for i in range(len(b)):
        D = np.array([[kGA[i] * b[i] ** 2 - r.density * r.area * om[i] ** 2, -1j * b[i] * kGA[i]],
                      [1j * b[i] * kGA[i], EI[i] * b[i] ** 2 + kGA[i] - r.density * r.second_moment_of_area * om[i] ** 2]])
        Hm = np.array([[H[0][i], H[1][i]], [H[2][i], H[3][i]]])
        assert np.allclose(Hm @ D, np.eye(2), atol=1e-10), i


@pytest.mark.parametrize("beta,f", [(0.3, 1100.0), (2.0, 700.0), (-4.1, 1300.0)])
def test_the_lattice_sums_equal_their_partial_sums(beta, f):
    om = 2 * np.pi * f
    m = np.arange(-200000, 200001)  # the even entries' tail is about 1 / M of the sum (measured 2e-6), the odd ones' 1 / M^2
    H = lg.free_beam_matrix(beta + m * TRACK.beta0, om, TRACK)
    S = beam_lattice_sums(beta, om, TRACK)
    for k, tol in ((0, 1e-5), (1, 1e-12), (2, 1e-12), (3, 1e-5)):
        assert abs(S[k] / np.sum(H[k]) - 1) < tol, (k, S[k], np.sum(H[k]))


def test_a_vanishing_moment_spring_gives_todays_vertical_tables():
    """k_theta = 1e-3 N m/rad (nine orders below the sourced value) through the two-channel path against the
    one-channel tables of today's model; fraction 0 holds the static point (column 0 at beta = 0)."""
    for fraction in (0.0,):  # the static point's class (the others take the same two-channel path without it)
        a0 = moving.receptance_table(TRACK, 60.0, 4, fraction=fraction)
        at = moving.receptance_table(with_k(TRACK, 1e-3), 60.0, 4, fraction=fraction)
        assert np.max(np.abs(at.A - a0.A)) < 1e-6 * np.max(np.abs(a0.A)), fraction  # measured 1.5e-8
        a1 = moving.receptance_table(with_k(TRACK, K_THETA), 60.0, 4, fraction=fraction)
        assert np.max(np.abs(a1.A - a0.A)) > 1e-3 * np.max(np.abs(a0.A)), fraction  # the spring acts (measured 1 %)


def test_a_vanishing_moment_spring_gives_todays_head_tables():
    js = np.arange(-6, 7)
    kinds = ("psiM", "psiF", "dpsiF", "wM")
    m0 = lg.moving_head_matrix(lg.RailHead(TRACK), 60.0, 0.0, js, kinds=kinds)
    mt = lg.moving_head_matrix(lg.RailHead(with_k(TRACK, 1e-3)), 60.0, 0.0, js, kinds=kinds)
    for k in kinds:
        assert np.max(np.abs(mt[k] - m0[k])) < 1e-8 * np.max(np.abs(m0[k])), k  # measured 3e-11


def test_the_stationary_receptance_refuses_the_moment_spring():
    with pytest.raises(ValueError, match="track.pad.rotational_stiffness"):
        stationary_receptance(0.0, 0.0, 2 * np.pi * 1000.0, with_k(TRACK, K_THETA))


def clamped_clamped_frequency(rail: Rail, L: float, f_lo: float, f_hi: float) -> float:
    """The lowest bending frequency [Hz] of an undamped Timoshenko span of length L clamped at both ends
    (w = psi = 0), from the sign change of the 4 x 4 boundary determinant of the free waves exp(lambda x)."""
    EI, kGA = rail.youngs_modulus * rail.second_moment_of_area, rail.shear_coefficient * rail.shear_modulus * rail.area
    rA, rI = rail.density * rail.area, rail.density * rail.second_moment_of_area

    def det(f):
        w = 2 * np.pi * f
        a, b, c = kGA * EI, kGA * (rI * w**2 - kGA) + rA * w**2 * EI + kGA**2, rA * w**2 * (rI * w**2 - kGA)
        d = np.sqrt(b * b - 4 * a * c + 0j)
        lam = [s * np.sqrt(m + 0j) for m in ((-b + d) / (2 * a), (-b - d) / (2 * a)) for s in (1, -1)]
        M = np.array([[1.0, (kGA * x * x + rA * w**2) / (kGA * x), np.exp(x * L), (kGA * x * x + rA * w**2) / (kGA * x) * np.exp(x * L)]
                      for x in lam]).T
        return np.linalg.det(M / np.abs(M).max(0)).imag  # the determinant is imaginary (its real part vanishes)

    f = np.arange(f_lo, f_hi, 1.0)
    d = np.array([det(x) for x in f])
    i = np.where(np.sign(d[1:]) != np.sign(d[:-1]))[0][0]
    from scipy.optimize import brentq
    return brentq(det, f[i], f[i + 1], xtol=1e-6)


def test_the_clamped_span_frequency_formula_gives_the_pinned_pinned_one_for_pinned_ends():
    """The determinant's frequency for clamped ends, checked on its own: the same span's pinned-pinned frequency
    (rail.track.pinned_pinned_frequency, closed form) lies below it, and the Euler-Bernoulli ratio (4.730 / pi)^2 = 2.27
    bounds their ratio from above (shear and rotary inertia lower the clamped span's frequency more)."""
    f_cc = clamped_clamped_frequency(RAIL, TRACK.L, 300.0, 3000.0)
    f_pp = pinned_pinned_frequency(TRACK)
    assert 1490.0 < f_cc < 1505.0, f_cc  # measured 1,497 Hz
    assert 1.0 < f_cc / f_pp < (4.730 / np.pi) ** 2


def _mid_span_peak(track, k, f):
    a = np.array([abs(direct.stationary_beam_rotational(track.L / 2, 2 * np.pi * fi, track, k, n=30)[0]) for fi in f])
    i = int(np.argmax(a))
    y0, y1, y2 = np.log(a[i - 1 : i + 2])
    return float(f[i] + 0.5 * (y0 - y2) / (y0 - 2 * y1 + y2) * (f[1] - f[0]))


def test_a_stiff_moment_spring_moves_the_mid_span_resonance_to_the_clamped_span():
    """On rigid supports (pad and ballast 1e12 N/m, no sleeper mass) the direct solution's mid-span resonance:
    at the pinned-pinned frequency without the spring, rising with k_theta, within 2 % of the clamped-clamped
    frequency at k_theta = 1e9 N m/rad (93 EI / L)."""
    rigid = Track(RAIL, Pad(1e12, 0.0, 0.0), Sleeper(0.0, 0.6), Ballast(1e12, 0.0, 0.0), "hysteretic")
    f_cc = clamped_clamped_frequency(RAIL, rigid.L, 300.0, 3000.0)
    f_pp = pinned_pinned_frequency(rigid)
    peaks = [_mid_span_peak(rigid, k, np.arange(f0 - 48, f0 + 48, 6.0))
             for k, f0 in ((1e-6, 1070.0), (K_THETA, 1075.0), (1e7, 1120.0), (1e8, 1320.0), (1e9, 1470.0))]
    assert abs(peaks[0] / f_pp - 1) < 5e-3, (peaks[0], f_pp)
    assert np.all(np.diff(peaks) > 0), peaks
    assert abs(peaks[-1] / f_cc - 1) < 0.02 and peaks[-1] < f_cc, (peaks, f_cc)


@pytest.mark.slow
@pytest.mark.parametrize("k", [K_THETA, 3 * K_THETA, 1e8])
@pytest.mark.parametrize("f", [900.0, 1100.0, 1300.0])
def test_the_receptances_with_the_moment_spring_agree_with_the_direct_solution(k, f):
    """The moving-load coefficients at V = 0.02 m/s (the stationary limit) summed over the load's position,
    alpha(x0) = sum_n a_n exp(i n beta0 x0), |n| <= 16 (as tests/test_head_positions.py), against the direct
    solution with 2 x 150 supports. Measured at 1,100 Hz with k_theta = 6.6e5: w/F within 5.6e-3 above a sleeper
    (the series' truncation at the support's kink), 2.5e-4 at quarter-span, 7e-6 at mid-span; psi/M within 4e-4.
    With k_theta = 1e8 the rotation is held at the supports and psi/M there is small and cusped: it is judged at
    quarter- and mid-span only."""
    t = with_k(TRACK, k)
    om = 2 * np.pi * f
    K = 16
    n = np.arange(-K, K + 1)
    ns, an, _ = moving.moving_coefficients(t, 0.02, om, K, rtol=1e-6)
    m = lg.moving_head_matrix(lg.RailHead(t), 0.02, om, n, kinds=("psiM", "psiF"), rtol=1e-6)
    kc = complex(support_rotational_stiffness(t, om))
    quarter = None
    for where, x0 in (("quarter-span", t.L / 4), ("above a sleeper", 0.0), ("mid-span", t.L / 2)):
        ph = np.exp(1j * n * t.beta0 * x0)
        wF, pF, pM = direct.stationary_beam_rotational(x0, om, t, kc, n=150)
        ours_w = complex(np.sum(an * ph))
        assert abs(ours_w / wF - 1) < 1e-2, (where, ours_w, wF)
        if k < 1e8 or where != "above a sleeper":
            ours_pM = complex(np.sum(m["psiM"][:, K] * ph))
            assert abs(ours_pM / pM - 1) < 1e-2, (where, ours_pM, pM)
        ours_pF = complex(np.sum(m["psiF"][:, K] * ph))
        if where == "quarter-span":
            quarter = pF
            assert abs(ours_pF / pF - 1) < 1e-2, (where, ours_pF, pF)
        else:  # zero by symmetry: judged against the quarter-span value
            assert abs(ours_pF) < 1e-3 * abs(quarter), (where, ours_pF, quarter)


def test_the_moment_spring_is_refused_on_a_track_cell_at_start_up(defaults, schema):
    """A cell's supports (rail.cell) carry no moment: track.pad.rotational_stiffness > 0 with track.cell is one
    line naming the key, before any table; 0 (the default) on a cell, and the spring on the uniform track, pass."""
    from rail.setup import build
    from rail.setup.config import deep_merge, validate_config

    cell = {"track": {"cell": {"bays": 2, "damper": {"mass": 4.0, "frequency": 1070.0, "loss_factor": 0.35, "position": 0.5}}},
            "roughness": {"bays": 2}}
    on_cell = validate_config(deep_merge(defaults, deep_merge(cell, {"track": {"pad": {"rotational_stiffness": K_THETA}}})), schema)
    problems = build.physics_problems(on_cell, "scen.yaml")
    assert [p for p in problems if "rotational_stiffness" in p] == [
        f"scen.yaml: track.pad.rotational_stiffness = {K_THETA!r} N m/rad is not allowed with track.cell: the pads' moment springs "
        "are carried on the uniform track only (rail.moving, rail.creepage.rail_flexibility); use 0 on a cell, or the rotational stiffness "
        "on a track without track.cell."]
    assert not [p for p in build.physics_problems(validate_config(deep_merge(defaults, cell), schema), "s") if "rotational" in p]
    uniform = validate_config(deep_merge(defaults, {"track": {"pad": {"rotational_stiffness": K_THETA}}}), schema)
    assert build.physics_problems(uniform, "s") == []
    assert build.scenario(uniform).track.pad.rotational_stiffness == K_THETA
    assert build.scenario(validate_config(defaults, schema)).track.pad.rotational_stiffness == 0.0  # today's pad
