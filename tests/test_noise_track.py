"""The track's own transfer (rail.noise.own_track, docs/noise.md "The track's own transfer"): each
piece against an independent calculation (the decay-length integral by quadrature, the cylinder's
radiation by integrating its far field, the contact force against rail.interaction's harmonic
balance), the default track against CNOSSOS-EU's L_H,TR of its class, a softer pad's louder rail,
and the option through rail.studies.noise.

The comparison with Table G-3a. The default track (pad 350 MN/m, concrete monoblock: CNOSSOS-EU's
"medium" class by rail.noise.cnossos.pad_class) is compared with L_H,TR(monoblock, medium). The
tolerance in each band is the class spread, |L_H,TR(soft) - L_H,TR(hard)| of the monoblock columns
in that band: the own transfer of a medium-class track should be no further from the medium class
than the soft class is from the hard one. Measured (docs/noise.md), own - medium, dB:
250 Hz -14.7, 315 -12.4, 400 -9.0, 500 -4.1 (the sleepers, which L_H,TR holds and the own transfer
leaves out), 630 +1.5, 800 +4.0, 1000 +5.2, 1250 +3.6 (the track's own decay rate and a contact
resonance at mid-span, docs/noise.md), 1600 +2.3, 2000 +1.3, 2500 +0.4, 3150 -0.2, 4000 -0.1, 5000 -1.2. The fast test asserts
the class spread at 2000-4000 Hz, where the rail's vertical vibration carries the track's noise and
the model holds; the slow one states the whole range.
"""

import dataclasses
import math

import numpy as np
import pytest
from scipy import integrate
from scipy.special import h1vp, hankel1

from rail import decay
from rail import interaction as I
from rail import track as T
from rail.moving import MovingReceptance
from rail.noise import cnossos as C
from rail.noise import own_track as O
from rail.noise import rolling as R


@pytest.fixture(scope="module")
def scn():
    from rail.app import api

    return api.load("default").scenario


def _own(track, scn, f_min, f_max, per_band, bays=64):
    # the decay rate on the bay-sampled positions to 64 bays: at the slowest decay of the default track
    # in these bands (0.5 dB/m) the response has fallen 19 dB there, so the sum misses about 1 %
    d = decay.decay_distances(track.L, bays, "bay_sampled")
    dec = decay.track_decay_rate(track, f_min=f_min, f_max=f_max, per_band=per_band, distances=d)
    return O.own_track_transfer(track, scn.wheels.mass, scn.spring, f_min=f_min, f_max=f_max, per_band=per_band, decay=dec)


def _band(f):
    return list(C.cnossos_frequency_bands().nominal).index(f)


# --- the pieces ------------------------------------------------------------------------------------


@pytest.mark.parametrize("rate", [0.3, 1.0, 12.0])
def test_decay_length_is_the_integral_of_the_squared_decay_over_both_directions(rate):
    beta = rate / (20 * math.log10(math.e))  # Np/m of the amplitude
    numeric, err = integrate.quad(lambda x: math.exp(-2 * beta * abs(x)), -np.inf, np.inf)
    assert float(O.decay_length(rate)) == pytest.approx(numeric, rel=1e-8)


@pytest.mark.parametrize("bad", [0.0, -1.0, math.nan, math.inf])
def test_decay_length_refuses_a_rate_that_is_not_finite_and_positive(bad):
    with pytest.raises(ValueError, match="decay_rate = .* dB/m is not allowed"):
        O.decay_length(bad)


@pytest.mark.parametrize("ka", [0.05, 0.5, 1.0, 3.0])
def test_cylinder_radiation_ratio_equals_its_far_field_power(ka):
    # the oscillating cylinder's pressure p = A H_1(kr) cos(theta), A from the surface velocity U cos(theta)
    # (time factor exp(-i omega t)); the intensity Re(p v*)/2 integrated over a circle at r = 40 m,
    # normalised by rho c times the mean-square normal velocity U^2/4 over the perimeter 2 pi a
    rho, c, a, U = 1.21, 343.0, 0.1, 1.0
    k = ka / a
    A = 1j * rho * c * U / h1vp(1, ka)
    r = 40.0
    theta = np.linspace(0, 2 * np.pi, 721)
    p = A * hankel1(1, k * r) * np.cos(theta)
    v = A * k * h1vp(1, k * r) * np.cos(theta) / (1j * k * rho * c)  # radial velocity, dp/dr / (i omega rho)
    power = integrate.trapezoid(0.5 * np.real(p * np.conj(v)) * r, theta)
    sigma = power / (rho * c * U**2 / 4 * 2 * np.pi * a)
    assert float(O.cylinder_radiation_ratio(ka)) == pytest.approx(sigma, rel=1e-4)


def test_cylinder_radiation_ratio_has_its_dipole_and_plane_wave_limits():
    assert float(O.cylinder_radiation_ratio(0.01)) == pytest.approx(math.pi / 2 * 0.01**3, rel=1e-3)
    assert float(O.cylinder_radiation_ratio(200.0)) == pytest.approx(1.0, abs=1e-3)
    # the rail's equivalent radius 2b/pi: ka = 1 at c / (2 pi a) = 572 Hz, sigma 0.74 there, 1 above 3 kHz
    f1 = 343.0 / (2 * math.pi * 2 * 0.150 / math.pi)
    assert f1 == pytest.approx(571.7, abs=0.1)
    assert float(O.rail_radiation_efficiency(f1)) == pytest.approx(float(O.cylinder_radiation_ratio(1.0)))
    assert float(O.rail_radiation_efficiency(5000.0)) == pytest.approx(1.0, abs=0.01)


def test_rigid_wheel_receptance_is_rail_interactions_wheel(scn):
    om = 2 * np.pi * np.array([50.0, 500.0, 5000.0])
    np.testing.assert_allclose(O.rigid_wheel_receptance(om, scn.wheels.mass), scn.wheels.receptance(om), rtol=1e-14)


def test_contact_force_equals_rail_interactions_force_for_one_wheel_on_a_continuous_track(scn):
    # rail.interaction solves eq. 21 for a wheel over a harmonic roughness; on a track without
    # parametric excitation (a continuously supported rail: a diagonal moving receptance) its force
    # harmonic is the stationary contact force of rail.noise.own_track.contact_force
    tr, L, V, K = scn.track, scn.track.L, 30.0, 12
    om0 = 2 * np.pi * V / L
    h = np.arange(-K, K + 1)
    A = np.zeros((1, h.size, h.size), dtype=complex)
    for i, m in enumerate(h):
        if m != 0:
            A[0, i, i] = T.continuous_support_receptance(m * om0, tr)
    tab = MovingReceptance(V, K, np.array([0.0]), A, np.zeros_like(A, dtype=float), 0)
    wheels = dataclasses.replace(scn.wheels, positions=(0.0,), creepage=None)
    m = 5  # wavelength L / 5 = 120 mm, 250 Hz at 30 m/s
    amp = 20e-6
    res = I.solve_forces(tab, wheels, scn.spring, I.Roughness.harmonic(amp, L / m, L, K), L)
    om = m * om0
    expected = O.contact_force(amp / 2, O.rigid_wheel_receptance(om, wheels.mass), T.continuous_support_receptance(om, tr),
                               1 / scn.spring.stiffness(om))
    assert abs(res.P[0, K + m]) == pytest.approx(float(expected), rel=1e-10)
    # and the sign of the receptances matters: with the wheel's receptance of the other sign the force differs
    wrong = O.contact_force(amp / 2, -O.rigid_wheel_receptance(om, wheels.mass), T.continuous_support_receptance(om, tr),
                            1 / scn.spring.stiffness(om))
    assert abs(abs(res.P[0, K + m]) - float(wrong)) > 1e-3 * float(expected)


def test_rail_sound_power_is_the_line_source_over_the_decay_length():
    # W = rho c (2 b) sigma <v^2> / beta, by hand: 1 mm/s rms, 1 dB/m, sigma 1, b = 0.15 m
    w = O.rail_sound_power(1e-6, 1.0, 1.0, 0.15, 1.21, 343.0)
    assert float(w) == pytest.approx(1.21 * 343.0 * 0.30 * 1e-6 * 8.685889638, rel=1e-9)


# --- the default track against CNOSSOS-EU's class ------------------------------------------------


def test_own_transfer_of_the_default_track_is_within_the_class_spread_of_its_cnossos_class(scn):
    assert C.pad_class(scn.track.pad.stiffness) == "medium"
    o = _own(scn.track, scn, 2000.0, 4000.0, per_band=1)
    i = [_band(f) for f in o.frequency]
    medium = C.track_transfer("monoblock", "medium")[i]
    spread = np.abs(C.track_transfer("monoblock", "soft") - C.track_transfer("monoblock", "hard"))[i]
    diff = o.transfer - medium
    assert np.all(np.abs(diff) <= spread), f"own - medium {np.round(diff, 2)} dB against the class spread {spread} dB"
    # and the own transfer is the rail's: W = 2 rails x the line source, the pieces recombined by hand
    k = O.rail_sound_power(10 ** (o.velocity_dB / 10) * o.sigma, o.decay_rate, 1.0)
    np.testing.assert_allclose(o.transfer, 10 * np.log10(2 * k.mean(axis=0) / 1e-12), atol=0.3)  # sigma varies inside a band


@pytest.mark.slow
def test_own_transfer_of_the_default_track_against_cnossos_250_to_5000_hz(scn):
    o = _own(scn.track, scn, 250.0, 5000.0, per_band=O.PER_BAND)
    i = [_band(f) for f in o.frequency]
    diff = o.transfer - C.track_transfer("monoblock", "medium")[i]
    spread = np.abs(C.track_transfer("monoblock", "soft") - C.track_transfer("monoblock", "hard"))[i]
    f = o.frequency
    # 1.6-4 kHz: within the class spread; 5 kHz: within the 3 dB
    assert np.all(np.abs(diff[(f >= 1600) & (f <= 4000)]) <= spread[(f >= 1600) & (f <= 4000)])
    assert abs(diff[f == 5000][0]) <= 3.0
    # 250-400 Hz: the rail alone is below the class, which holds the sleepers, by more than the spread
    low = f <= 400
    assert np.all(diff[low] < -spread[low])


# --- a softer pad ------------------------------------------------------------------------------------


def test_a_softer_pad_decays_more_slowly_and_its_rail_is_louder_at_the_pinned_pinned_frequency(scn):
    f_pp = T.pinned_pinned_frequency(scn.track)
    f = min(C.cnossos_frequency_bands().nominal, key=lambda x: abs(math.log(x / f_pp)))
    soft = dataclasses.replace(scn.track, pad=dataclasses.replace(scn.track.pad, stiffness=7.0e7))  # config/scenarios/soft_pad.yaml
    a = _own(scn.track, scn, f, f, per_band=2, bays=128)
    b = _own(soft, scn, f, f, per_band=2, bays=128)
    assert np.all(b.decay_rate < a.decay_rate)  # a longer decay length at both contact positions
    assert b.transfer[0] > a.transfer[0] + 1.0  # a louder rail: the decay length is the difference's source


# --- the option through the noise of a growth run ---------------------------------------------------


def test_the_own_option_replaces_the_track_transfer_and_nothing_else(scn):
    own = tuple(np.linspace(70.0, 110.0, 24))
    t = R.Track("monoblock", None, own=own)
    np.testing.assert_array_equal(t.transfer(), own)
    rail = C.rail_roughness_class("M")
    coach = R.Vehicle("coach", axles=4, brake="disc", wheel_diameter=0.92, wheel_load=50e3)
    traffic = [R.TrafficClass(coach, vehicles_per_hour=10, speed=40.0)]
    a = R.rolling_noise(rail, R.Track("monoblock", "medium"), traffic)
    b = R.rolling_noise(rail, t, traffic)
    np.testing.assert_allclose(b.power_vehicle, a.power_vehicle)  # the vehicle part is CNOSSOS-EU's, unchanged
    np.testing.assert_allclose(b.power_track - a.power_track,
                               (np.array(own) - C.track_transfer("monoblock", "medium"))[None, :], atol=1e-12)
    with pytest.raises(ValueError, match="own: the track's own transfer must be 24 finite levels"):
        R.Track("monoblock", None, own=(1.0,) * 23)


def test_the_settings_read_track_transfer_and_refuse_another_value(default_study):
    from rail.setup import build, config

    assert build.noise_settings(default_study.config).track_transfer == "cnossos"
    cfg = config.deep_merge(default_study.config, {"figures": {"noise": {"track_transfer": "own"}}})
    config.validate_config(cfg, config.project_schema())
    assert build.noise_settings(cfg).track_transfer == "own"
    bad = config.deep_merge(default_study.config, {"figures": {"noise": {"track_transfer": "twins"}}})
    with pytest.raises(config.ConfigError, match="figures.noise.track_transfer"):
        config.validate_config(bad, config.project_schema())


def test_a_pad_without_a_cnossos_class_has_noise_with_the_own_transfer():
    from rail.app import api
    from rail.setup import config, inputs

    cfg = api.load("soft_pad").config
    assert "no CNOSSOS-EU pad class" in inputs.noise_problem(cfg, 40.0)
    own = config.deep_merge(cfg, {"figures": {"noise": {"track_transfer": "own"}}})
    assert inputs.noise_problem(own, 40.0) is None


def test_noise_outputs_take_the_own_transfer_and_say_so(default_study):
    # a given own transfer (24 levels) replaces L_H,TR in the sound power of the track and nothing else:
    # the track's power changes by own - L_H,TR(medium) in every band, the vehicle's not at all
    import xarray as xr

    from rail.setup import build, config
    from rail.studies import noise as N

    n = np.arange(3) * 1e5
    J, j = 64, 12
    Z = np.zeros((3, 2 * J + 1), complex)
    Z[:, J + j] = Z[:, J - j] = 2e-6 * 1.5 ** np.arange(3) / 2
    growth = xr.Dataset({"Z_real": (("passage", "h"), Z.real), "Z_imag": (("passage", "h"), Z.imag)}, coords={"passage": n},
                        attrs={"bays": 1, "speed_m_per_s": 40.0})
    levels = np.linspace(70.0, 110.0, 24)
    own = O.OwnTrackTransfer(frequency=C.cnossos_frequency_bands().nominal.astype(float), transfer=levels,
                             excitation=np.array([0.0, 0.3]), decay_rate=np.ones((2, 24)), mobility_dB=np.zeros((2, 24)),
                             force_dB=np.zeros((2, 24)), velocity_dB=np.zeros((2, 24)), sigma=np.ones(24),
                             power_rail_dB=np.zeros((2, 24)), per_band=4, description="given")
    cfg = default_study.config
    cfg_own = config.deep_merge(cfg, {"figures": {"noise": {"track_transfer": "own"}}})
    a = N.noise_outputs(growth, cfg, default_study.scenario, "default", build.noise_settings(cfg)).data
    b = N.noise_outputs(growth, cfg_own, default_study.scenario, "default", build.noise_settings(cfg_own), own_transfer=own).data
    np.testing.assert_allclose(b["sound_power_track"].values - a["sound_power_track"].values,
                               np.broadcast_to(levels - C.track_transfer("monoblock", "medium"), (3, 24)), atol=1e-9)
    np.testing.assert_allclose(b["sound_power_vehicle"].values, a["sound_power_vehicle"].values)
    np.testing.assert_array_equal(b["track_transfer"].values, levels)
    np.testing.assert_array_equal(b["track_transfer_cnossos"].values, C.track_transfer("monoblock", "medium"))
    assert b["own_track_decay_rate"].attrs["units"] == "dB/m" and b["contact_position"].attrs["units"] == "m"
    assert b.attrs["track_transfer"] == "own" and a.attrs["track_transfer"] == "cnossos"
    assert "track transfer: the track's own" in N.noise_csv_text(b, "default")
    with pytest.raises(ValueError, match="own_transfer holds 23 bands"):
        N.noise_outputs(growth, cfg_own, default_study.scenario, "default", build.noise_settings(cfg_own),
                        own_transfer=dataclasses.replace(own, transfer=levels[:23]))
