"""The linear method with dynamic creepage (rail.growth_spectrum.creepage, rail.contact.tangent) against
the probes of the nonlinear march with u_bar (rail.creepage.coupling.march_with_creepage), and with every mechanism
off bit for bit the tangent march as it was (tests/reference/tangent_fixed_creepage.py).

The mechanisms are those of the dynspeed_* cases of config/studies/dynamic_creepage_speeds.yaml (the trailer and the motored wheelset of
dyn_trailer.yaml and dyn_driven.yaml, the rail head's rod and bending of dyn_rail.yaml, Polach's
dry-rail falling friction), on the tests' track (tests/test_growth.py) with reduced numerics.
"""

import dataclasses
import functools

import numpy as np
import pytest
from model import scenario
from test_growth import MATERIAL, contact_spring, track

import reference.tangent_fixed_creepage as frozen
from rail.creepage import coupling
from rail import chain, moving, wear
from rail import growth_spectrum as GS
from rail.contact import solve_tangential, tangent
from rail.creepage.modes import periodic_response
from rail.growth_spectrum import creepage, linear
from rail.interaction import Roughness
from rail.creepage.rail_flexibility import RailHead
from rail.creepage.wheelset import Wheelset, wheelset_modes

K, NODES = 24, 31
R_W = MATERIAL.wheel_radius
TRAILER = Wheelset("torsional", R_W, wheel_inertia=45.0, centre_inertia=14.0, axle_stiffness=5.5e6, damping=0.01)
MOTORED = Wheelset("torsional", R_W, wheel_inertia=50.0, centre_inertia=20.0, axle_stiffness=5.5e6, motor_inertia=288.0,
                   coupling_stiffness=3.6e6, damping=0.02)
FALLING = dict(friction_static=0.3, friction_dynamic=0.12, friction_decay=1.67)
MECHANISMS = ("trailer", "motored", "rail", "falling", "together")


def material(mechanism: str, tr):
    """The contact material with one mechanism of dynamic creepage (or 'together': the motored wheelset, the
    rail's flexibility and falling friction; 'none': the report's)."""
    m = MATERIAL
    if mechanism in ("trailer", "motored", "together"):
        m = dataclasses.replace(m, longitudinal=wheelset_modes(TRAILER if mechanism == "trailer" else MOTORED))
    if mechanism in ("rail", "together"):
        m = dataclasses.replace(m, rail_flexibility=RailHead(tr))
    if mechanism in ("falling", "together"):
        m = dataclasses.replace(m, **FALLING)
    return m


_TABLES = {}


def case(mechanism: str, pad: float = 3.5e8, speed: float = 40.0, bays: int = 2, normal: str = "report", path: str = "wheel"):
    """(scenario, tables) of one mechanism on the tests' track with the pad stiffness ``pad`` [N/m]."""
    tr = track(pad)
    scn = scenario(tr, material(mechanism, tr), contact_spring(), K=K, nodes=NODES)
    scn = dataclasses.replace(scn, roughness=dataclasses.replace(scn.roughness, bays=bays),
                              contact_numerics=dataclasses.replace(scn.contact_numerics, normal=normal, path=path))
    key = (pad, speed, bays)
    if key not in _TABLES:
        _TABLES[key] = moving.bloch_tables(tr, speed, K, bays)
    return scn, _TABLES[key]


def probes(scn, tabs, lines, monkeypatch, **kw):
    """The reference: rate_spectrum's probes with the nonlinear march's Newton steps on u_bar converged to
    1e-9 of the creep velocity (rail.creepage.coupling.march_with_creepage's tol; its default 1e-5 leaves part of a probe's own
    small change of u_bar unresolved: 3.4 % of the rate at the comb line of 1 kHz with the rail's flexibility,
    test_the_default_probes_leave_part_of_a_probes_u_bar_unresolved)."""
    with monkeypatch.context() as mp:
        mp.setattr(coupling, "march_with_creepage", functools.partial(coupling.march_with_creepage, tol=1e-9, max_iter=200))
        return GS.rate_spectrum(scn, tabs, lines, grid_phases=1, check_lines=1, method="probe", **kw)


def agree(fast, ref):
    """The issue's measure: every line's rate (and the other eigenvalue of a locked line) within 1 % of the
    spectrum's largest abs(rate), the growth rate's sign the same wherever it exceeds that 1 %. Returns the
    largest error over that largest rate."""
    big = np.abs(ref.rate).max()
    err = max(np.abs(fast.rate - ref.rate).max(), np.abs(fast.rate_other - ref.rate_other).max()) / big
    assert err < 0.01, (err, fast.rate, ref.rate)
    clear = np.abs(ref.growth_rate) > 0.01 * big
    assert np.array_equal(np.sign(fast.growth_rate[clear]), np.sign(ref.growth_rate[clear])), (fast.growth_rate, ref.growth_rate)
    return err


@pytest.mark.parametrize("mechanism", ["trailer", "motored", "falling", pytest.param("rail", marks=pytest.mark.slow),
                                       pytest.param("together", marks=pytest.mark.slow)])
def test_linear_method_with_dynamic_creepage_matches_the_probes(mechanism, monkeypatch):
    """At 40 m/s on the default pad, a half-comb line (54.5 mm, 730 Hz): the tangent with the loop of u_bar
    closed against the probes of the nonlinear march. The mechanism must move the rate (else the check would
    pass without it): measured against the fixed creepage's rate, by more than five times the agreement.
    (The rail's flexibility, whose converged probes take 20-60 s, the comb line of 1 kHz and the full matrix: the
    slow tests.)"""
    scn, tabs = case(mechanism)
    lines = [11]
    fast = GS.rate_spectrum(scn, tabs, lines, grid_phases=1, check_lines=1, method="linear")
    ref = probes(scn, tabs, lines, monkeypatch)
    assert fast.method == "linear" and ref.method == "probe"
    err = agree(fast, ref)
    fixed = GS.rate_spectrum(case("none")[0], tabs, lines, grid_phases=1, check_lines=1, method="linear")
    moved = np.abs(fixed.rate - ref.rate).max() / np.abs(ref.rate).max()
    assert moved > 5 * err, (mechanism, moved, err)


@pytest.mark.slow
def test_linear_method_with_dynamic_creepage_on_free_lines_of_a_four_bay_period(monkeypatch):
    """Free lines (classes 1 and 3, complex Bloch directions and their harmonics of u_bar) and a half-comb
    line of a four-bay period, every mechanism together."""
    scn, tabs = case("together", bays=4)
    lines = [21, 23, 42]
    fast = GS.rate_spectrum(scn, tabs, lines, grid_phases=1, check_lines=1, method="linear")
    agree(fast, probes(scn, tabs, lines, monkeypatch))


@pytest.mark.slow
@pytest.mark.matrix  # 20 cases of converged probes (1-7 min each): run on demand, python -m pytest -m matrix -n 2
@pytest.mark.parametrize("mechanism", MECHANISMS)
@pytest.mark.parametrize("pad", [3.5e8, 1e9])
@pytest.mark.parametrize("speed", [40.0, 60.0])
def test_linear_method_with_dynamic_creepage_matches_the_probes_over_the_full_matrix(mechanism, pad, speed, monkeypatch):
    """The full matrix: every mechanism alone and together, the default and the stiff (1e9 N/m) pad, 40
    and 60 m/s, the 2-bay lines from 120 to 25 mm at five per octave (the dynspeed scenarios' survey)."""
    scn, tabs = case(mechanism, pad, speed)
    lines = GS.spectrum_lines(scn.L, 2, K, 0.025, 0.12, 5)
    fast = GS.rate_spectrum(scn, tabs, lines, grid_phases=1, check_lines=1, method="linear")
    agree(fast, probes(scn, tabs, lines, monkeypatch))


@pytest.mark.slow
def test_the_default_probes_leave_part_of_a_probes_u_bar_unresolved(monkeypatch):
    """Why the reference's Newton steps are tightened: with the rail's flexibility at the comb line of 1 kHz
    (40 mm at 40 m/s), the probes at march_with_creepage's default tolerance (1e-5 of the creep velocity)
    differ from the converged probes by more than 1 % (measured 3.4 %), the linear method from the converged
    ones by less than 1e-3 (measured 3e-5)."""
    scn, tabs = case("rail")
    lines = [30]
    fast = GS.rate_spectrum(scn, tabs, lines, grid_phases=1, check_lines=1, method="linear")
    loose = GS.rate_spectrum(scn, tabs, lines, grid_phases=1, check_lines=1, method="probe")
    tight = probes(scn, tabs, lines, monkeypatch)
    assert abs(loose.rate[0] - tight.rate[0]) > 0.01 * abs(tight.rate[0])
    assert abs(fast.rate[0] - tight.rate[0]) < 1e-3 * abs(tight.rate[0])


@pytest.mark.parametrize("normal,path", [("report", "wheel"), ("nonhertzian", "patch")])
def test_linear_method_without_dynamic_creepage_is_bit_for_bit_the_tangent_march_as_it_was(normal, path, monkeypatch):
    """Every mechanism off: the extended tangent march (u_bar, falling friction and the force carried along)
    gives today's numbers bit for bit: the spectrum (free and locked lines; on the patch's true path with
    the pressure shape and the step times' directions) against the same spectrum with the tangent march
    as it was (tests/reference/tangent_fixed_creepage.py) put in its place, in this process."""
    scn, tabs = case("none", bays=4, normal=normal, path=path)
    lines = [5, 7, 6, 4, 30]
    now = GS.rate_spectrum(scn, tabs, lines, grid_phases=1, check_lines=1, method="linear")
    monkeypatch.setattr(linear, "work_tangent", frozen.work_tangent)
    before = GS.rate_spectrum(scn, tabs, lines, grid_phases=1, check_lines=1, method="linear")
    for name in ("rate", "rate_other", "operator", "sideband", "source"):
        assert np.array_equal(getattr(now, name), getattr(before, name)), name


def _passage(mechanism="none", dP=0.05):
    """A one-bay passage of the tests' scenario over a roughness of one harmonic (varying force)."""
    scn, tabs = case(mechanism, bays=1)
    Z = np.zeros(2 * K + 1, dtype=complex)
    Z[K + 3] = Z[K - 3] = 5e-6
    f = chain.solve_forces(scn, tabs[0], Roughness(Z, 1))
    return scn, wear.march_inputs(f, 0, Roughness(Z, 1), scn.material, scn.contact_numerics)


def test_tangent_of_the_march_with_u_bar_and_falling_friction_against_finite_differences():
    """The tangent march's new directions and output against central differences of the nonlinear march
    (solve_tangential with ubar): the derivative of the tangential force and of the work along a change of
    u_bar, and along force, half-length and u_bar together with falling friction. A difference with a step
    small enough that no stick/slip set changes (here 1e-12 m of u_bar, 0.1 N of force) agrees to rounding (measured
    4e-9 in the norm; ten times larger steps move a node's set and the difference is 1e-3 off); the tangent holds
    the sets."""
    scn, mi = _passage()
    V, n = 40.0, mi.P.size
    t = np.arange(n)
    ub0 = 2e-8 * np.sin(2 * np.pi * t / 900) + 3e-6 * t / n
    cols = np.stack([1e-9 * np.cos(2 * np.pi * t / 40), 1e-9 * np.sin(2 * np.pi * t / 333)], 1)
    dP = np.stack([100 * np.cos(2 * np.pi * t / 250), np.zeros(n)], 1)
    da = dP * 2e-9
    for m in (scn.material, dataclasses.replace(scn.material, **FALLING)):
        z = np.zeros((n, 2))
        work, dwork, Q, dQ = tangent.work_tangent(mi.P, mi.a, m, V, mi.delta, mi.M, dP if m.friction_decay else z,
                                                  da if m.friction_decay else z, ubar=ub0, dubar=cols, force=True)
        base = solve_tangential(mi.P, mi.a, m, V, mi.delta, mi.M, ubar=ub0)
        np.testing.assert_array_equal(base.Q, Q)
        np.testing.assert_array_equal(base.work, work)
        for c in range(2):
            h = 1e-3
            run = [solve_tangential(mi.P + s * h * (dP[:, c] if m.friction_decay else 0), mi.a + s * h * (da[:, c] if m.friction_decay else 0),
                                    m, V, mi.delta, mi.M, ubar=ub0 + s * h * cols[:, c]) for s in (1, -1)]
            fQ = (run[0].Q - run[1].Q) / (2 * h)
            fw = (run[0].work - run[1].work) / (2 * h)
            assert np.linalg.norm(fQ - dQ[:, c]) < 1e-3 * np.linalg.norm(dQ[:, c]), (m.friction_decay, c)
            assert np.linalg.norm(fw - dwork[:, c]) < 1e-3 * np.linalg.norm(dwork[:, c]), (m.friction_decay, c)


def test_periodic_response_tangents_against_the_periodic_response():
    """The wheelset's response in the harmonic basis (discrete_mode_response) against periodic_response of a
    cosine, and its tangent along the step times (periodic_response_dt) against central differences, for the
    motored wheelset (a free rotation and two elastic modes) on non-uniform steps."""
    modes = wheelset_modes(MOTORED)
    n, dt0 = 3000, 1e-5
    k = np.arange(n)
    for q in (1, 7, 60):
        x = periodic_response(np.cos(2 * np.pi * q * k / n), np.full(n, dt0), modes)[0]
        H = creepage.discrete_mode_response(modes, dt0, [q, -q], n)
        want = 0.5 * (H[0] * np.exp(2j * np.pi * q * k / n) + H[1] * np.exp(-2j * np.pi * q * k / n)).real
        assert np.abs((x - x.mean()) - (want - want.mean())).max() < 1e-9 * np.abs(want).max()
    F = 1000 * np.cos(2 * np.pi * 3 * k / n) + 300 * np.sin(2 * np.pi * 7 * k / n) + 50
    dt = dt0 * (1 + 0.1 * np.sin(2 * np.pi * 2 * k / n))
    ddt = np.stack([1e-7 * np.cos(2 * np.pi * 5 * k / n), 1e-7 * np.exp(2j * np.pi * 11 * k / n)], 1)
    d = creepage.periodic_response_dt(F, dt, modes, ddt)
    for c in range(2):
        for part in (np.real, np.imag):
            if not np.any(part(ddt[:, c])):
                continue
            h = 1e-3
            fd = (periodic_response(F, dt + h * part(ddt[:, c]), modes)[0] - periodic_response(F, dt - h * part(ddt[:, c]), modes)[0]) / (2 * h)
            an = part(d[:, c])
            assert np.abs((fd - fd.mean()) - (an - an.mean())).max() < 1e-6 * np.abs(an).max()


def test_the_tangent_march_refuses_the_wheelsets_modes_inside_it():
    scn, mi = _passage("trailer")
    z = np.zeros((mi.P.size, 1))
    with pytest.raises(ValueError, match="longitudinal"):
        tangent.work_tangent(mi.P, mi.a, scn.material, 40.0, mi.delta, mi.M, z, z)


def _cold_check(scn, tabs, j, kind, eps, op, monkeypatch):
    """The linearity check as it was (locked_matrix: probes of 2 eps by the nonlinear march from u_bar = 0, each on its
    own grid), its Newton steps converged to 1e-9 of the creep velocity: the change of the faster eigenvalue's real part
    against the operator op."""
    from rail.growth_spectrum import spectrum as SP
    s_n, t_n = SP._period(scn, tabs, kind)
    with monkeypatch.context() as mp:
        mp.setattr(coupling, "march_with_creepage", functools.partial(coupling.march_with_creepage, tol=1e-9, max_iter=200))
        Z0n = SP.smooth_roughness(s_n)
        W0n = chain.train_wear(s_n, t_n, Z0n, 0.0)[0]
        M2 = SP.locked_matrix(s_n, t_n, j * kind // scn.roughness.bays, 2 * eps, 0.0, Z0n, W0n)
    return abs(SP.sorted_eigenvalues(M2)[0].real / SP.sorted_eigenvalues(op)[0].real - 1), W0n


def test_the_linearity_check_with_u_bar_measures_what_converged_probes_do_and_grows_with_the_amplitude(monkeypatch):
    """With u_bar the check's probes of 2 eps start their Newton steps from the linear prediction (linear.warm_train_wear,
    one or two marches against five to ten from u_bar = 0). At a half-comb line of the motored wheelset it measures what
    the check as it was measures with its Newton steps converged (1e-9): 1.4604e-5 against 1.4612e-5 at eps = 1 nm,
    7.44e-3 against 7.33e-3 at 30 um; it grows with the amplitude (a check that could not fail would not). The comb's
    source is the smooth rail's converged wear (measured 1.4e-8 of it off train_wear's over two bays converged to 1e-9;
    march_with_creepage's default 1e-5, the source until 2026-12-02, is 6.7e-4 off)."""
    scn, tabs = case("motored")
    lines = [11, 10]
    small = GS.rate_spectrum(scn, tabs, lines, eps=1e-9, grid_phases=1, check_lines=1, method="linear")
    cold, W0 = _cold_check(scn, tabs, 11, 2, 1e-9, small.operator[0], monkeypatch)
    assert abs(small.linearity - cold) < 0.05 * cold, (small.linearity, cold)
    big = GS.rate_spectrum(scn, tabs, lines, eps=3e-5, grid_phases=1, check_lines=1, method="linear")
    cold_big, _ = _cold_check(scn, tabs, 11, 2, 3e-5, big.operator[0], monkeypatch)
    assert abs(big.linearity - cold_big) < 0.05 * cold_big, (big.linearity, cold_big)
    assert big.linearity > 100 * small.linearity and big.linearity > 5e-3
    # the source at the comb line 10 (the 1-bay line 5), against the converged train_wear over two bays (its line 10)
    assert abs(small.source[1] - 2 * abs(W0[len(W0) // 2 + 10])) < 1e-6 * small.source[1]


def test_the_accelerated_reference_is_march_with_creepages_periodic_state():
    """creepage_reference's Newton steps accelerated (Anderson mixing of march_with_creepage's own steps) reach the
    periodic state of march_with_creepage's plain steps to the same tolerance, in fewer marches (measured to 1e-8: 9
    against 10 on dynspeed_together at 40 m/s; on the tests' track 0-2 fewer, the rail's flexibility the most)."""
    scn, tabs = case("motored", bays=1)
    Z = np.zeros(2 * K + 1, dtype=complex)
    f = chain.solve_forces(scn, tabs[0], Roughness(Z, 1))
    mi = wear.march_inputs(f, 0, Roughness(Z, 1), scn.material, scn.contact_numerics)
    ref = creepage.creepage_reference(mi, scn.material, 40.0, scn.contact_numerics, K)
    _, info = coupling.march_with_creepage(mi, scn.material, 40.0, scn.contact_numerics, tol=1e-12, max_iter=80, harmonics=K)
    st = info["state"]
    dp = ref.p - st.p
    assert np.abs(dp - dp.mean()).max() < 1e-7 * np.abs(st.p - st.p.mean()).max()
    assert abs(ref.vbar - st.vbar) < 1e-7 * max(abs(st.vbar), 1e-300) or abs(ref.vbar - st.vbar) < 1e-12


def test_a_train_of_two_wheels_on_the_patchs_path_takes_the_linear_method_and_matches_the_probes(monkeypatch):
    """The wheel behind rolls on the wear of the wheel before it, so on the patch's true path its step times are not
    exactly uniform (about 1e-8 of their mean): until 2026-12-02 that sent every train of more than one wheel with the
    dynamic creepage to the probes (found on a four-axle locomotive of a fleet, 4 times the cost). The spread is measured
    here between the old limit and creepage.STEP_TIMES_HELD, the linear method is taken, and it matches converged
    probes on the half-comb line as one wheel does."""
    scn, _ = case("motored", normal="nonhertzian", path="patch")
    scn = dataclasses.replace(scn, wheels=dataclasses.replace(scn.wheels, positions=(0.0, 2.5)))
    tabs = moving.bloch_tables(track(3.5e8), 40.0, K, 2, offsets=(0.0, -2.5, 2.5))
    smooth = Roughness(GS.probes.smooth_roughness(scn), 2)
    f0 = chain.solve_forces(scn, tabs, smooth)
    first, behind = (int(l) for l in np.argsort(scn.wheels.positions)[::-1])
    worn = wear.apply_wear(smooth, chain.passage_wear(scn, f0, smooth, first, 0.0, None).Z)
    mi = wear.march_inputs(f0, behind, worn, chain.wheel_material(scn, behind), scn.contact_numerics, 0.0)
    spread = np.ptp(mi.dt) / np.mean(mi.dt)
    assert 1e-9 < spread < creepage.STEP_TIMES_HELD, spread
    lines = [11]
    fast = GS.rate_spectrum(scn, tabs, lines, grid_phases=1, check_lines=1, method="linear")
    assert fast.method == "linear", fast.method
    agree(fast, probes(scn, tabs, lines, monkeypatch))
