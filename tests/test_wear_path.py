"""The wear on the patch's true path (issue 42; docs/contact.md, "The patch's true path"): the patch
centred c(x_w) from the wheel steps uniformly over the rail while the wheel moves at V, so each
step lasts dt = Delta (1 - dc/dx) / V. Its wear against the quasi-steady limit derived in
docs/contact.md, and the report's option unchanged."""

import dataclasses

import numpy as np
import pytest
from scipy.special import j0
from test_contact_shift import A0, MATERIAL, R, K, _spring, _track

from model import scenario

from rail import chain, moving
from rail import contact as C
from rail import interaction as I

L = 0.6


@pytest.fixture(scope="module")
def table():
    return moving.receptance_table(_track(), 40.0, K, offsets=[0.0])


def _scn(normal, path):
    s = scenario(_track(), MATERIAL, _spring(), K=K)
    return dataclasses.replace(s, contact_numerics=C.ContactNumerics(41, "default", 1.0, normal, path))


def _carter_exponent():
    """e = d ln Q / d ln gamma of Carter's steady solution at the static load (rail.contact.steady.carter, an
    analytic formula independent of the march): 2 (1 - x) x / (1 - (1 - x)^2), x = |gamma| / (pi k mu p0)."""
    def Q(g):
        return abs(C.carter(np.zeros(1), 1e5, dataclasses.replace(MATERIAL, creepage=g), 40.0, R)[2])
    g = MATERIAL.creepage
    return (np.log(Q(g * 1.001)) - np.log(Q(g / 1.001))) / (2 * np.log(1.001))


def _wear_harmonic(table, normal, path, k, amp):
    s = _scn(normal, path)
    rough = I.Roughness.harmonic(amp, L / k, L, K)
    w = chain.passage_wear(s, chain.solve_forces(s, table, rough), rough)
    return w.Z[K + k] / rough.Z[K + k], float(w.depth.mean())


@pytest.mark.parametrize("normal,k,tol", [("nonhertzian", 2, 0.01), ("report", 2, 0.01), ("nonhertzian", 5, 0.025)])
def test_the_true_path_adds_the_quasi_steady_wear_of_a_moving_patch_for_long_waves(table, normal, k, tol):
    # Derived in docs/contact.md: in steady rolling the particles cross a patch moving at V (1 + c')
    # while the rigid slip stays gamma V, so the creepage the tangential problem sees is gamma / (1 + c');
    # the work per unit area is |gamma_eff| Q(gamma_eff) / (2b), so the wear carries
    # -(1 + e) c' w_bar, e = d ln Q / d ln gamma (0 in full slip, 1 at vanishing creepage; 0.82 here).
    # With c = R_w r' J0(beta a) (R_w r' for the report's model) and r = Delta cos(beta x) that is a
    # wear harmonic (1 + e) w_bar R_w beta^2 J0(beta a) per unit roughness, in phase with it (more wear
    # on the crests: a decay). It holds for waves long against the patch: measured 0.5 % from it at
    # lambda / 2a = 24 (k = 2) and 1.3 % at 9.5 (k = 5); the unsteady contact lags it at shorter waves.
    beta = 2 * np.pi * k / L
    amp = 1e-4 / (R * beta**2)  # R_w kappa = 1e-4: the linear regime
    patch, wbar = _wear_harmonic(table, normal, "patch", k, amp)
    wheel, _ = _wear_harmonic(table, normal, "wheel", k, amp)
    filt = j0(beta * A0) if normal == "nonhertzian" else 1.0
    expected = (1 + _carter_exponent()) * wbar * R * beta**2 * filt
    change = patch - wheel
    assert change.real == pytest.approx(expected, rel=tol)
    assert abs(change.imag) < 0.01 * abs(change)  # in phase with the roughness (measured 0.03 deg at k = 2)
    # the term is as large as the growth the model reports: here 1.8 times the estimate w_bar R_w beta^2 J0
    assert abs(change) > 1.5 * wbar * R * beta**2 * filt


def test_the_correction_is_linear_in_the_roughness(table):
    # halving the roughness halves the change (per unit roughness the same, to 1e-3 of it)
    k = 5
    beta = 2 * np.pi * k / L
    amp = 1e-4 / (R * beta**2)
    big = _wear_harmonic(table, "nonhertzian", "patch", k, amp)[0] - _wear_harmonic(table, "nonhertzian", "wheel", k, amp)[0]
    small = (_wear_harmonic(table, "nonhertzian", "patch", k, amp / 2)[0]
             - _wear_harmonic(table, "nonhertzian", "wheel", k, amp / 2)[0])
    assert abs(small - big) < 1e-3 * abs(big)


def test_on_a_smooth_rail_the_true_path_is_the_wheel_path(table):
    # no roughness, no move of the centre: the same wear to rounding
    rough = I.Roughness.smooth(K)
    out = {}
    for path in ("wheel", "patch"):
        s = _scn("nonhertzian", path)
        out[path] = chain.passage_wear(s, chain.solve_forces(s, table, rough), rough).depth
    np.testing.assert_allclose(out["patch"], out["wheel"], rtol=1e-12)


def test_the_wear_path_is_checked_naming_the_key():
    with pytest.raises(ValueError, match=r"contact\.wear_path = 'centre' is not allowed: it must be one of \['wheel', 'patch'\]"):
        C.ContactNumerics(41, "default", 1.0, "report", "centre")
