"""The linearised wear feedback per wavenumber (rail.growth_spectrum) against full nonlinear growth
runs, for a growing and a decaying wavelength between the one-bay comb lines."""

import contextlib
import dataclasses
import io
import re
import signal

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from model import scenario
from test_growth import MATERIAL, contact_spring, track

from rail import chain, moving
from rail import growth_spectrum as GS
from rail import interaction as I

K, N = 24, 4


@pytest.fixture(scope="module")
def setup():
    tr = track()
    scn = scenario(tr, MATERIAL, contact_spring(), K=K, nodes=41, passages=100000, step=10000)
    scn = dataclasses.replace(scn, roughness=dataclasses.replace(scn.roughness, bays=N))
    return scn, moving.bloch_tables(tr, 40.0, K, N)


def test_batches_hold_one_line_per_pair_of_classes():
    b = GS.batches([5, 9, 6, 3, 7, 8, 1], 4)
    for batch in b:
        keys = [min(j % 4, (4 - j % 4) % 4) for j in batch]
        assert len(keys) == len(set(keys))
    assert sorted(j for batch in b for j in batch) == [1, 3, 5, 6, 7, 8, 9]


def test_linear_rates_predict_full_growth_runs(setup):
    # lines between the comb lines of the 4-bay period at 40 m/s: j = 37 (64.9 mm, grows by about
    # 5 % per 1e5 passages) and j = 86 (27.9 mm, decays by about 18 %). The probe is in its linear
    # range (eps and 2 eps agree to 1e-4). A full growth run from 0.1 um sinusoids at both lines
    # (100,000 passages, 10 updates, varying contact grids, the parametric wear of the smooth rail
    # in class 0 beside them) ends where the growth loop's own explicit update (1 - h R_j)^10 says,
    # (measured 3e-4 and 1.1e-3), and within the update-step error of exp(-R_j n) (first order,
    # estimated 10 |h R|^2 / 2 = 0.07 % and 1.4 %; measured 0.09 % and 1.3 %).
    scn, tabs = setup
    lines = [37, 86]
    R = GS.wear_rates(scn, tabs, lines, eps=1e-8)
    R2 = GS.wear_rates(scn, tabs, lines, eps=2e-8)
    assert np.abs(R2 / R - 1).max() < 1e-4
    assert -R[0].real > 0 > -R[1].real  # one grows, one decays
    J = N * K
    Z = np.zeros(2 * J + 1, dtype=complex)
    for j in lines:
        Z[J + j] = Z[J - j] = 1e-7 / 2
    h = chain.grow(scn, tabs, I.Roughness(Z, N), progress=io.StringIO())
    g = scn.growth
    steps, hstep = g.passages // g.passages_per_update, g.passages_per_update  # one wheel: train = wheel passages
    for j, r in zip(lines, R):
        ratio = h.Z[-1][J + j] / h.Z[0][J + j]
        assert abs(abs(ratio) - 1) > 0.03  # changed measurably
        assert abs(ratio / (1 - hstep * r) ** steps - 1) < 2e-3
        assert abs(ratio / np.exp(-r * g.passages) - 1) < 1.5 * steps * abs(hstep * r) ** 2 / 2 + 1e-3


def test_spectrum_lines_are_finer_than_a_tenth_of_a_third_octave():
    # 48 bays: 20 mm to 0.6 m with neighbours never further apart than 2^(1/30), the classes
    # balanced so that the wear evaluations (one line per pair of classes each) are few
    lines = GS.spectrum_lines(0.6, 48, 64, 0.02, 0.6, 30)
    lam = 48 * 0.6 / lines
    ratio = lam[:-1] / lam[1:]
    assert lam[0] == pytest.approx(0.6) and lam[-1] <= 0.02 < lam[-2]
    assert 1 < ratio.min() and ratio.max() <= 2 ** (1 / 30)
    assert len(GS.batches(lines, 48)) <= int(np.ceil(len(lines) / 25)) + 1
    with pytest.raises(ValueError, match=r"a roughness period of 16 bays spaces the lines by 6\.2 % at 0\.6 m, coarser than "
                                         r"1/30 octave \(2\.3 %\): use at least 43 bays"):
        GS.spectrum_lines(0.6, 16, 64, 0.02, 0.6, 30)
    with pytest.raises(ValueError, match=r"shortest = 0\.005 m is not allowed: it must be >= L / K = 0\.009375 m"):
        GS.spectrum_lines(0.6, 48, 64, 0.005, 0.6, 30)


@contextlib.contextmanager
def _within(seconds: float):
    """Fail (rather than hang) if the block runs longer than seconds (SIGALRM; the walk is pure Python)."""
    def expired(signum, frame):
        raise AssertionError(f"did not return within {seconds} s")

    previous = signal.signal(signal.SIGALRM, expired)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def test_spectrum_lines_start_at_the_longest_wavelength_when_its_division_rounds_down():
    # 1 bay of 0.6 m, longest 0.1 m: 0.6 / 0.1 = 5.999..., the first line is j = 6 (0.1 m), and the
    # walk moves on from it (it never did from j = 5, 0.12 m, whose next line is 20 % away)
    with _within(5):
        lines = GS.spectrum_lines(0.6, 1, 64, 0.02, 0.1, 4)
    assert lines[0] == 6 and 0.6 / lines[-1] <= 0.02 < 0.6 / lines[-2]  # 0.1 m down to 20 mm
    assert np.all(np.diff(lines) > 0) and (lines[1:] / lines[:-1]).max() <= 2 ** (1 / 4)
    with pytest.raises(ValueError, match=r"a roughness period of 1 bays spaces the lines by 20 % at 0\.12 m, coarser than "
                                         r"1/4 octave \(19 %\): use at least 2 bays"), _within(5):
        GS.spectrum_lines(0.6, 1, 64, 0.02, 0.11, 4)
    with pytest.raises(ValueError, match=r"a roughness period of 1 bays \(0\.6 m\) is shorter than longest = 1 m: use at least 2 bays"):
        GS.spectrum_lines(0.6, 1, 64, 0.02, 1.0, 1)
    with pytest.raises(ValueError, match=r"bays = 0 is not allowed: it must be an integer >= 1"):
        GS.spectrum_lines(0.6, 0, 64, 0.02, 0.1, 4)


_wavelength = st.one_of(st.floats(0.0, 2.0), st.sampled_from([0.0, 0.1, 0.3, 0.6, 1.2, -0.1, float("nan"), float("inf")]))


@settings(max_examples=300, deadline=2000)
@given(bays=st.one_of(st.integers(-2, 200), st.sampled_from([2.0, 2.5, True, float("nan")])), shortest=_wavelength,
       longest=_wavelength, per_octave=st.one_of(st.integers(-1, 120), st.sampled_from([10**10, 30.0, 0.5])))
def test_spectrum_lines_are_distinct_increasing_and_span_the_range_or_are_refused(bays, shortest, longest, per_octave):
    # every setting returns in bounded time (the deadline; the alarm turns a hang into a failure):
    # lines 1 <= j <= N K, increasing, neighbours within 2^(1 / per_octave), from the line at or just
    # beyond the longest wavelength down to the first at or below the shortest (or to L / K)
    L, K = 0.6, 64
    try:
        with _within(10):
            lines = GS.spectrum_lines(L, bays, K, shortest, longest, per_octave)
    except ValueError as e:
        assert re.search(r"bays|shortest|longest|per_octave", str(e)), str(e)
        return
    lo = L / K if shortest == 0 else shortest
    lam = bays * L / lines
    assert lines.dtype.kind == "i" and 1 <= lines[0] and lines[-1] <= bays * K
    assert np.all(np.diff(lines) > 0)
    assert np.all(lines[1:] <= lines[:-1] * 2 ** (1 / per_octave) * (1 + 1e-12))
    assert longest * (1 - 1e-9) <= lam[0] < longest * 2 ** (1 / per_octave)
    assert np.all(lam[:-1] > lo) and (lam[-1] <= lo or lines[-1] == bays * K)


@pytest.mark.slow
def test_locked_line_operator_predicts_a_growth_run_from_a_sine(setup):
    # j = 86 of 4 bays is on the half-comb (class N/2, 2L/(2k+1) = 27.9 mm): the roughness at +j and
    # -j couple through the supports, so the cosine and the sine are probed separately on the 2-bay
    # period (line 43) and the 2 x 2 operator M is used. A full growth run over the 4 bays from a
    # 0.1 um sine at j = 86 (10 updates, varying grids) ends where the loop's explicit update
    # (I - h M)^10 says (to 2e-3 of the amplitude, as the free lines) and within its step error of
    # expm(-M n)
    from scipy.linalg import expm

    scn, tabs = setup
    s2 = dataclasses.replace(scn, roughness=dataclasses.replace(scn.roughness, bays=2))
    M, W0 = GS.locked_operator(s2, (tabs[0], tabs[N // 2]), 43)
    assert np.abs(W0[len(W0) // 2 + 43]) < 1e-12 * np.abs(W0).max()  # no parametric source off the comb
    sp = GS.rate_spectrum(scn, tabs, [86], grid_phases=1)
    assert sp.locked[0] == 2 and sp.growth_rate[0] == pytest.approx(-np.linalg.eigvals(M).real.min(), rel=1e-9)
    J = N * K
    b0 = 1e-7
    Z = np.zeros(2 * J + 1, dtype=complex)
    Z[J + 86], Z[J - 86] = -0.5j * b0, 0.5j * b0  # b0 sin(2 pi 86 x / (N L)): Z_j = (a - i b) / 2
    h = chain.grow(scn, tabs, I.Roughness(Z, N), progress=io.StringIO())
    g = scn.growth
    steps, hstep = g.passages // g.passages_per_update, g.passages_per_update
    zj = h.Z[-1][J + 86]
    got = np.array([2 * zj.real, -2 * zj.imag])
    explicit = np.linalg.matrix_power(np.eye(2) - hstep * M, steps) @ [0.0, b0]
    exact = expm(-M * g.passages) @ [0.0, b0]
    assert abs(np.hypot(*got) / b0 - 1) > 0.03  # changed measurably
    assert np.abs(got - explicit).max() < 2e-3 * b0
    step_error = steps * np.linalg.norm(hstep * M, 2) ** 2 / 2
    assert np.abs(got - exact).max() < (1.5 * step_error + 1e-3) * b0


@pytest.mark.slow
def test_closure_study_rate_at_1000_hz_is_the_spectrum_rate_plus_its_source(root):
    # The closure study's in-phase rate at 1000 Hz is -Re(Delta Z_m / Z_m) after one passage over a
    # 10 um cosine at L/m = 40 mm (40 m/s, m = 15; rail/studies/closure.py). The spectrum gives it
    # to first order as -M[0, 0] (the cosine's own wear, locked operator on the comb) minus
    # Re(W0_m / Z_m) (the smooth rail's source at the line). For every closure value of the closure
    # study: the same sign, and a difference no larger than an O(A) nonlinearity extrapolated from
    # halving the amplitude; that nonlinearity is itself below 1.5 % of the largest rate
    import yaml

    values = yaml.safe_load((root / "config/studies/closure_study.yaml").read_text())["defaults"]["sweep"]["contact.closure_scale"]
    tr = track()
    Kc, m = 48, 15
    tab = moving.receptance_table(tr, 40.0, Kc)
    rows = []
    for s in values:
        scn = scenario(tr, MATERIAL, contact_spring(), K=Kc, nodes=41, closure_scale=s)
        closure = {}
        for A in (1e-5, 5e-6):
            rough = I.Roughness.harmonic(A, 0.6 / m, 0.6, Kc)
            w = chain.passage_wear(scn, chain.solve_forces(scn, tab, rough), rough)
            closure[A] = -np.real(w.Z[Kc + m] / rough.Z[Kc + m])
        Mc, W0 = GS.locked_operator(scn, tab, m)
        predicted = -Mc[0, 0] - np.real(W0[Kc + m]) / (1e-5 / 2)
        rows.append((s, closure[1e-5], closure[5e-6], predicted))
    rows = np.array(rows)
    scale = np.abs(rows[:, 3]).max()
    assert np.all(np.sign(rows[:, 1]) == np.sign(rows[:, 3])), rows
    assert np.all(np.abs(rows[:, 1] - rows[:, 3]) <= 2 * np.abs(rows[:, 1] - rows[:, 2]) + 1e-3 * scale), rows
    assert np.abs(rows[:, 1] - rows[:, 2]).max() < 0.015 * scale, rows


def _rigid_tables(speed, K, N):
    """Receptance tables of a rigid, uniform track (no rail displacement, no supports passing)."""
    from rail.moving import MovingReceptance

    def table(r):
        n = 2 * K + 1 if r == 0 else 2 * K
        return MovingReceptance(speed, K, np.array([0.0]), np.zeros((1, n, n), complex), np.zeros((1, n, n)), 0, r / N)

    return tuple(table(r) for r in range(N // 2 + 1))


@pytest.mark.slow
def test_rigid_track_spectrum_reduces_to_steady_rolling():
    # A rigid, uniform track: the force is that of the wheel mass on the contact spring over the
    # roughness, P_beta / Z_beta = 1 / (1 / k_H(omega) - 1 / (m omega^2)), and for wavelengths long
    # against the patch the contact is quasi-static, so the wear rate is that of steady rolling:
    # depth = (K / rho) |gamma| Q(P, R) / (2b) with Carter's Q (rail.contact.carter, analytic),
    # 1/R = 1/R_w + kappa, kappa = beta^2 z: R_qs = d_P P_beta / Z_beta + d_kappa beta^2.
    # Averaged over 8 contact grids (the rate of one grid carries the derivative of the grid-tied
    # error, 1.3-2.5 % here), the full unsteady model's rate lags R_qs by a phase proportional to
    # 2a / lambda (the contact's memory: -0.84 (2a / lambda) rad, to 1 %), which vanishes with
    # 2a / lambda, and its magnitude is R_qs's to 0.47 % at every wavelength (41 nodes; about 0.28 % at
    # 81: the discretisation's error of the derivative of the steady work)
    from rail import contact as C

    tr = track()
    Kr, Nr, V = 8, 8, 20.0
    scn = scenario(tr, MATERIAL, contact_spring(), K=Kr, nodes=41)
    scn = dataclasses.replace(scn, roughness=dataclasses.replace(scn.roughness, bays=Nr))
    m, wl, P0, Rw = scn.material, scn.wear_law, scn.wheels.static_load, scn.wheels.radius

    def depth(P, kappa):
        Q = C.carter(np.zeros(1), P, m, V, 1.0 / (1.0 / Rw + kappa))[2]
        return wl.depth(abs(m.creepage) * abs(Q) / (2 * m.half_width))

    hP, hk = 1e-5 * P0, 1e-3
    dP = (depth(P0 + hP, 0.0) - depth(P0 - hP, 0.0)) / (2 * hP)
    dk = (depth(P0, hk) - depth(P0, -hk)) / (2 * hk)
    a0 = float(C.hertz_half_length(P0, Rw, m))
    lines = np.array([1, 2, 4])  # 4.8, 2.4 and 1.2 m
    tabs = _rigid_tables(V, Kr, Nr)
    R = np.mean([GS.wear_rates(scn, tabs, lines, eps=1e-9, grid_phase=p) for p in np.arange(8) / 8], axis=0)
    beta = 2 * np.pi * lines / (Nr * tr.L)
    om = beta * V
    Pz = 1.0 / (1.0 / scn.spring.stiffness(om) - 1.0 / (scn.wheels.mass * om**2))
    R_qs = dP * Pz + dk * beta**2
    x = 2 * a0 * lines / (Nr * tr.L)  # 2a / lambda
    lag = np.angle(R / R_qs) / x
    assert np.ptp(lag) < 0.01 * abs(lag.mean()) and -1.0 < lag.mean() < -0.7, lag
    dev = np.abs(R / R_qs) - 1
    assert np.all(np.abs(dev) < 0.006), dev


@pytest.mark.slow
def test_class_operator_predicts_the_sidebands_of_a_growth_run(setup):
    # Within a Bloch class the supports couple a line j to its sidebands j +- N. A full growth run
    # (4 bays, 100,000 passages, 10 updates) from a 0.1 um cosine at j = 65 (36.9 mm, near the
    # pinned-pinned frequency at 40 m/s) grows roughness at j +- 4: the diagonal alone (wear_rates)
    # predicts none there; the class operator over the lines 57..73 of class 1 predicts it
    # (expm(-C n), and the loop's own explicit update (I - h C)^10), within the grid-tied error of
    # its sideband entries
    from scipy.linalg import expm

    scn, tabs = setup
    window = [57, 61, 65, 69, 73]
    C, ev = GS.class_operator(scn, tabs, window)
    C0, _ = GS.class_operator(scn, tabs, window, grid_phases=1)
    assert np.allclose(np.diag(C0), GS.wear_rates(scn, tabs, window, eps=1e-9), rtol=1e-6)
    J = N * K
    Z = np.zeros(2 * J + 1, dtype=complex)
    Z[J + 65] = Z[J - 65] = 1e-7 / 2
    h = chain.grow(scn, tabs, I.Roughness(Z, N), progress=io.StringIO())
    g = scn.growth
    steps, hstep = g.passages // g.passages_per_update, g.passages_per_update
    z0 = np.array([Z[J + j] for j in window])
    got = np.array([h.Z[-1][J + j] for j in window])
    explicit = np.linalg.matrix_power(np.eye(len(window)) - hstep * C, steps) @ z0
    exact = expm(-C * g.passages) @ z0
    side = [1, 3]  # 61 and 69
    assert np.all(np.abs(got[side]) > 0.01 * abs(z0[2]))  # sidebands grew measurably (the diagonal says 0)
    # measured: 3.1 % and 0.35 % against the explicit update, 3.2 % and 4.1 % against expm (its step
    # error added); the sideband entries of C themselves vary by 8.5 % (C[61, 65]) and 2 % (C[69, 65])
    # over four contact grids (their grid-tied error), and the run averages five grids, C two
    assert np.all(np.abs(got[side] - explicit[side]) < 0.05 * np.abs(got[side])), (got, explicit)
    assert np.all(np.abs(got[side] - exact[side]) < 0.08 * np.abs(got[side])), (got, exact)
    assert abs(got[2] / explicit[2] - 1) < 4e-3  # measured 2.5e-3: the diagonal's grid-tied error, 0.1-0.4 % of |R| per grid


def test_growing_bands_are_the_runs_of_positive_rate():
    from rail.studies.rate_spectrum import growing_bands

    lam = np.array([0.6, 0.5, 0.4, 0.3, 0.2, 0.1])
    assert growing_bands(lam, np.array([-1, 1, 2, -1, 1, 1])) == [(0.5, 0.4), (0.2, 0.1)]
    assert growing_bands(lam, -np.ones(6)) == []
    assert growing_bands(lam[:1], np.array([1.0])) == [(0.6, 0.6)]


def test_sweep_rate_spectrum_puts_every_point_on_the_grid():
    # two swept keys (2 x 3): each point's spectrum lands at its grid index, and the fastest
    # wavelength is that of the largest growth at the point
    from rail.growth_spectrum import RateSpectrum
    from rail.studies.rate_spectrum import rate_spectrum_dataset, sweep_rate_spectrum

    lines = np.array([48, 60, 96])
    points, indices = [], []
    for i in range(2):
        for j in range(3):
            rate = -np.array([1.0, 2.0, 3.0]) * 1e-7 * (1 + i) * np.roll([1, 0.5, 0.2], j)
            sp = RateSpectrum(48 * 0.6 / lines, lines, np.array([1, 0, 1]), rate.astype(complex), rate.astype(complex),
                              np.zeros(3), np.zeros(3), np.zeros(3), 1e-4, 1e-9, 48, 2)
            points.append(rate_spectrum_dataset({40.0: sp}, 0.6, 1))
            indices.append((i, j))
    ds = sweep_rate_spectrum(points, ["track.pad.stiffness", "speed"], [[1e8, 3.5e8], [20.0, 40.0, 60.0]], indices, ["N/m", "m/s"])
    assert ds["growth_dB_per_1e5_trains"].dims == ("track_pad_stiffness", "speed", "wavelength")
    for p, (i, j) in zip(points, indices):
        np.testing.assert_array_equal(ds["growth_dB_per_1e5_trains"].values[i, j], p["growth_dB_per_1e5_trains"].values[0])
        np.testing.assert_array_equal(ds["growth_dB_per_1e5_axles"].values[i, j], p["growth_dB_per_1e5_axles"].values[0])
        assert ds["fastest_wavelength"].values[i, j] == p["wavelength"].values[np.argmax(p["growth_rate"].values[0])]
    assert ds["track_pad_stiffness"].attrs["units"] == "N/m"


def test_spectrum_figures_draw_the_lines_they_are_given(tmp_path):
    # the spectrum figure and the sweep map draw from datasets alone; their wavelength axis spans
    # the lines (no empty decades when the range is short)
    from rail.growth_spectrum import RateSpectrum
    from rail.plotting import studies as plots
    from rail.studies.rate_spectrum import rate_spectrum_dataset, sweep_rate_spectrum

    lines = np.arange(24, 61, 4)  # 4 bays: 100 mm to 40 mm
    spectra = {}
    for v in (20.0, 40.0):
        rate = (np.linspace(-1, 1, lines.size) * 1e-7 * v / 40).astype(complex)
        spectra[v] = RateSpectrum(4 * 0.6 / lines, lines, (lines % 4 == 0).astype(int), rate, rate, np.zeros(lines.size),
                                  np.zeros(lines.size), np.zeros(lines.size), 1e-4, 1e-9, 4, 1)
    ds = rate_spectrum_dataset(spectra, 0.6, 1)
    fig = plots.rate_spectrum_figure(ds)
    hi, lo = fig.axes[0].get_xlim()  # wavelength decreases to the right (rail.plotting.axes)
    assert 35 < lo < 40 and 100 < hi < 110  # mm
    fig.savefig(tmp_path / "s.png")
    sweep = sweep_rate_spectrum([ds.isel(speed=[i]) for i in range(2)], ["speed"], [[20.0, 40.0]], [(0,), (1,)], ["m/s"])
    plots.rate_spectrum_sweep_figure(sweep).savefig(tmp_path / "m.png")
    assert (tmp_path / "m.png").stat().st_size > 5000


def test_spectrum_of_a_train_of_four_wheels_is_plotted_and_summarised_per_axle_passage():
    # growth_dB_per_1e5_trains counts one passage of the whole train, growth_dB_per_1e5_axles one wheel:
    # a quarter of it for 4 wheels (both from the rate by hand); the figure draws the per-axle line
    # and the summary gives the fastest growth in both conventions
    from rail.growth_spectrum import RateSpectrum
    from rail.plotting import studies as plots
    from rail.studies.rate_spectrum import rate_spectrum_dataset, summary_markdown

    lines = np.arange(24, 61, 4)
    g = np.linspace(-1, 1, lines.size) * 1e-6
    sp = RateSpectrum(4 * 0.6 / lines, lines, np.zeros(lines.size, int), (-g).astype(complex), (-g).astype(complex),
                      np.zeros(lines.size), np.zeros(lines.size), np.zeros(lines.size), 1e-4, 1e-9, 4, 1)
    ds = rate_spectrum_dataset({40.0: sp}, 0.6, 4)
    per_train = 20 * np.log10(np.e) * g * 1e5
    np.testing.assert_allclose(ds["growth_dB_per_1e5_trains"].values[0], per_train, rtol=1e-12)
    np.testing.assert_allclose(ds["growth_dB_per_1e5_axles"].values[0], per_train / 4, rtol=1e-12)
    assert ds["growth_dB_per_1e5_trains"].attrs["units"] == "dB per 100000 train passages"
    ax = plots.rate_spectrum_figure(ds).axes[0]
    line = [ln for ln in ax.get_lines() if np.size(ln.get_xdata()) == lines.size]
    np.testing.assert_allclose(line[0].get_ydata(), per_train / 4, rtol=1e-12)
    row = summary_markdown(ds).splitlines()[2].split("|")
    assert float(row[4]) == pytest.approx(per_train.max(), abs=0.005) and float(row[5]) == pytest.approx(per_train.max() / 4, abs=0.005)


@pytest.mark.parametrize("normal,path", [("report", "wheel"), ("nonhertzian", "wheel"), ("nonhertzian", "patch"),
                                         ("report", "patch")])
def test_linear_method_matches_the_probes_of_the_nonlinear_march(setup, normal, path):
    """The spectrum's default path (the tangent of the contact march about the smooth rail, one bay)
    against the independent probes of the nonlinear march over the N bays (method 'probe'): free
    lines of both classes of a pair, a comb and a half-comb line, long and short wavelengths. The
    two differ by the probes' O(eps) nonlinearity and the tangent's difference of the influence
    matrix (measured: at most 3e-4 of |R| on this track); a wrong derivative term gives tens of
    percent (a step of 1e-6 in that difference instead of 1e-9 gave errors of order 1). On the patch's
    true path the tangent carries the derivative of the step times too (rail.contact.tangent, ddt)."""
    scn, tabs = setup
    scn = dataclasses.replace(scn, contact_numerics=dataclasses.replace(scn.contact_numerics, normal=normal, path=path))
    lines = [5, 7, 6, 4, 13, 30, 41, 90]
    fast = GS.rate_spectrum(scn, tabs, lines, grid_phases=1, check_lines=2, method="linear")
    ref = GS.rate_spectrum(scn, tabs, lines, grid_phases=1, check_lines=2, method="probe")
    err = np.abs(fast.rate - ref.rate) / np.abs(ref.rate)
    assert err.max() < 2e-3, dict(zip(lines, err))
    assert np.abs(fast.rate_other - ref.rate_other).max() < 2e-3 * np.abs(ref.rate).max()
    assert np.allclose(fast.sideband, ref.sideband, atol=2e-3)
    assert np.allclose(fast.source, ref.source, rtol=1e-9, atol=0)
    assert fast.linearity < 1e-2
    with pytest.raises(ValueError, match="method"):
        GS.rate_spectrum(scn, tabs, lines, grid_phases=1, method="exact")


def test_linear_method_falls_back_to_the_probes_where_a_probe_changes_the_contact_grid(setup, monkeypatch):
    """Where a probe's contact grid differs from the smooth rail's (seen in the closure sweep at
    40 m/s: 2764 against 2766 spacings per bay), the tangent march cannot be used; that grid phase
    takes the probes of the nonlinear march, and the spectrum says so (method attribute)."""
    scn, tabs = setup
    lines = [5, 6, 13]

    def mismatch(*args, **kwargs):
        raise GS.GridMismatch("the probe's contact grid (M 32, Nx 132672) differs from the smooth rail's")

    ref = GS.rate_spectrum(scn, tabs, lines, grid_phases=1, check_lines=1, method="probe")
    monkeypatch.setattr(GS.spectrum, "linear_rates", mismatch)
    fell = GS.rate_spectrum(scn, tabs, lines, grid_phases=1, check_lines=1, method="linear")
    assert fell.method.startswith("linear, probes at grid phase 0:")
    np.testing.assert_array_equal(fell.rate, ref.rate)
    assert ref.method == "probe"


def test_spectrum_progress_counts_every_probe_batch_and_changes_no_rate(setup):
    # issue 36: the spectrum job was silent for minutes; its progress lines count the probe batches
    # of every grid phase to the end, and reporting them changes no number
    scn, tabs = setup
    lines, told = [5, 7, 13], []
    quiet = GS.rate_spectrum(scn, tabs, lines, grid_phases=2, check_lines=1)
    loud = GS.rate_spectrum(scn, tabs, lines, grid_phases=2, check_lines=1, progress=told.append)
    assert np.array_equal(quiet.rate, loud.rate) and np.array_equal(quiet.grid_spread, loud.grid_spread)
    counts = [tuple(int(x) for x in re.match(r"(\d+) of (\d+) probe batches \(grid phase \d of 2, 3 lines\)$", t).groups())
              for t in told if "probe batches" in t]
    total = counts[-1][1]
    # from 0 (told before the first batch, issue 57) to the end
    assert [d for d, _ in counts] == list(range(0, total + 1)) and {n for _, n in counts} == {total} and total % 2 == 0
    assert sum(t.startswith("linearity check:") for t in told) == 1


@pytest.mark.parametrize("method", ["linear", "probe"])
def test_spectrum_progress_is_told_before_the_first_march_and_through_the_long_parts(setup, method):
    # issue 57, item 8: a one-train spectrum's log stayed empty for 648 s: the first line came only after
    # the first probe batch (a spectrum of a few lines has one or two), nothing during the tangent marches,
    # and nothing at all by the probes of the nonlinear march (method 'probe', taken with the wheelset's
    # or the rail's flexibility or falling friction)
    scn, tabs = setup
    told = []
    GS.rate_spectrum(scn, tabs, [5, 8], grid_phases=2, check_lines=1, method=method, progress=told.append)  # a free and a locked line
    unit = "probe batches" if method == "linear" else "probe steps"
    assert re.match(rf"0 of \d+ {unit} \(grid phase 1 of 2, 2 lines", told[0]), told[0]  # at once, before any work
    counts = [tuple(int(x) for x in re.match(rf"(\d+) of (\d+) {unit}", t).groups()) for t in told if unit in t]
    total = counts[-1][1]
    assert [d for d, _ in counts] == list(range(0, total + 1)) and total % 2 == 0
    if method == "linear":  # the tangent marches, one per wheel and grid phase, from 0 to the end
        marches = [tuple(int(x) for x in re.match(r"(\d+) of (\d+) tangent marches", t).groups()) for t in told if "tangent marches" in t]
        assert [d for d, _ in marches] == list(range(0, marches[-1][1] + 1)) and marches[-1][1] == 2 * len(scn.wheels.positions)
