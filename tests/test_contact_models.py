"""The contact house (issue 44): the normal-contact model as an object that knows its filter and its
patch, the one compliance, and the march and its tangent sharing their steps."""

import ast
import dataclasses
from pathlib import Path

import numpy as np
import pytest
from scipy.special import j0

from rail import contact as C
from rail import interaction as I
from rail.contact import models

ROOT = Path(__file__).resolve().parents[1]
MATERIAL = C.ContactMaterial(2.1e11, 0.3, 0.008, 0.46, 0.3, 0.3, -0.001)


def test_normal_contact_given_by_name_is_held_as_its_model_object():
    assert isinstance(C.ContactNumerics(41, "default", 1.0, "report", "wheel").normal, C.ReportNormal)
    nums = C.ContactNumerics(41, "default", 1.0, "nonhertzian", "wheel")
    assert isinstance(nums.normal, C.NonHertzianNormal) and nums.normal.name == str(nums.normal) == "nonhertzian"
    # replacing by name (as the tests and studies do) looks the model up again
    assert isinstance(dataclasses.replace(nums, normal="report").normal, C.ReportNormal)
    assert C.ContactNumerics(41, "default", 1.0, C.NonHertzianNormal(), C.WheelPath()) == nums


@pytest.mark.parametrize("bad", ["hertz", "", None, ["report"], float("nan")])
def test_an_unknown_normal_contact_is_refused_naming_the_key_and_the_choices(bad):
    with pytest.raises(ValueError, match=r"contact\.normal = .* is not allowed: it must be one of \['report', 'nonhertzian'\]"):
        C.ContactNumerics(41, "default", 1.0, bad, "wheel")


def test_the_report_model_sees_the_roughness_unfiltered_and_the_nonhertzian_through_J0():
    # report: a point spring on the roughness at the wheel centre (filter 1); the 2D patch: the
    # Chebyshev-weighted mean over the patch, J0(beta a) (Gradshteyn 3.753), zero at beta a = 2.405
    a0 = 6.3e-3
    beta = 2 * np.pi / np.array([0.5, 0.06, 0.02, 2 * np.pi * a0 / 2.404825557695773])
    np.testing.assert_array_equal(C.ReportNormal().filter(beta, a0), 1.0)
    got = C.NonHertzianNormal().filter(beta, a0)
    np.testing.assert_allclose(got, j0(beta * a0), rtol=1e-12, atol=1e-12)
    assert abs(got[-1]) < 1e-12


@pytest.mark.parametrize("model", [C.ReportNormal(), C.NonHertzianNormal()])
def test_both_models_give_the_hertz_patch_on_a_smooth_rail(model):
    # the analytic limit: no roughness, the Hertz half-length of eq 23 with R = R_w, the ellipse's
    # shape (factor 1) and no move of the centre
    P = np.linspace(6e4, 1.4e5, 9)
    M, delta = 30, 3e-4
    xi = (np.arange(2 * M + 1) - M) * delta
    smooth = I.Roughness.smooth(8)
    patch = model.patches(P, np.linspace(0, 0.5, P.size), np.arange(P.size), 64, smooth, 0.6, MATERIAL, xi)
    a_hertz = np.sqrt(4 * (1 - 0.3**2) * P * 0.46 / (np.pi * 0.008 * 2.1e11))  # eq 23 written out
    np.testing.assert_allclose(patch.a, a_hertz, rtol=1e-9)
    assert patch.shift < 1e-9 and patch.min_shape == pytest.approx(1.0, abs=1e-9)
    if patch.shape is not None:
        np.testing.assert_allclose(patch.shape[np.abs(xi)[None, :].repeat(P.size, 0) < 0.99 * patch.a[:, None]], 1.0, atol=1e-9)
    np.testing.assert_allclose(model.half_lengths(P, smooth, 0.6, MATERIAL), a_hertz, rtol=1e-9)


def test_the_compliance_is_one_quantity():
    # E = 210 GPa, nu = 0.3: k = 4 (1 - nu^2) / (pi E) = 5.5174e-12 1/Pa (worked by hand), E* = E / (2 (1 - nu^2))
    k = C.compliance(MATERIAL)
    assert k == pytest.approx(5.51737e-12, rel=1e-5)
    assert C.composite_modulus(MATERIAL) == pytest.approx(2.1e11 / 1.82, rel=1e-14)
    assert k == pytest.approx(2 / (np.pi * C.composite_modulus(MATERIAL)), rel=1e-15)
    assert C.report_rigid_compliance(MATERIAL) == pytest.approx(2 * k, rel=1e-15)
    a = C.hertz_half_length(1e5, 0.46, MATERIAL)
    assert a**2 == pytest.approx(k * 1e5 * 0.46 / 0.008, rel=1e-14)  # eq 23: a^2 = k P R / b


def _functions(path: Path):
    return {n.name: n for n in ast.walk(ast.parse(path.read_text())) if isinstance(n, ast.FunctionDef)}


def _called(fn: ast.FunctionDef) -> set[str]:
    return {n.func.id for n in ast.walk(fn) if isinstance(n, ast.Call) and isinstance(n.func, ast.Name)}


def test_the_march_and_its_tangent_call_the_same_steps():
    # the tangent march differentiates the march's own steps instead of re-typing them
    pkg = ROOT / "rail/contact"
    steps = {"_pressure", "_shift_particles", "_enter_particles", "_stick_solve", "_restore_rows", "_exit_slip", "_advance"}
    march = _called(_functions(pkg / "march.py")["_march"])
    tangent = _functions(pkg / "tangent.py")
    assert steps <= march and "_step_work_all" in march
    assert steps <= _called(tangent["_march_tangent"])
    own = _functions(pkg / "steps.py")  # both call the one step work
    assert "_work_terms_of" in _called(own["_step_work_all"]) and "_work_terms_of" in _called(tangent["_d_step_work"])


def test_no_module_outside_the_contact_package_asks_which_normal_model_it_has():
    # a comparison with a model's name ('report', 'nonhertzian') or an isinstance check on a model class
    offenders = []
    for f in sorted((ROOT / "rail").rglob("*.py")):
        if "contact" in f.relative_to(ROOT / "rail").parts[:1]:
            continue
        for n in ast.walk(ast.parse(f.read_text())):
            if isinstance(n, ast.Compare):
                consts = [c.value for c in [n.left, *n.comparators] if isinstance(c, ast.Constant)]
                if any(v in ("nonhertzian",) for v in consts) or (
                        "report" in consts and "normal" in ast.unparse(n)):
                    offenders.append(f"{f.relative_to(ROOT)}:{n.lineno}: {ast.unparse(n)}")
            if isinstance(n, ast.Call) and isinstance(n.func, ast.Name) and n.func.id == "isinstance":
                if any(s in ast.unparse(n) for s in ("ReportNormal", "NonHertzianNormal")):
                    offenders.append(f"{f.relative_to(ROOT)}:{n.lineno}: {ast.unparse(n)}")
    assert not offenders, "\n".join(offenders)


def test_the_structure_limits_of_the_contact_package():
    # issue 44: no module of rail/contact over 800 lines, no function over 150
    for f in sorted((ROOT / "rail/contact").glob("*.py")):
        assert len(f.read_text().splitlines()) <= 800, f.name
        for name, fn in _functions(f).items():
            assert fn.end_lineno - fn.lineno + 1 <= 150, f"{f.name}: {name}"


def test_the_contact_grid_sizes_the_patch_from_the_model():
    # rail.contact.passage asks the model for the half-lengths: the report's local-curvature patch on a
    # crest of curvature kappa is sqrt(R / R_w) of the smooth one, R = 1 / (1 / R_w + kappa) (eq 24)
    k = 10
    rough = I.Roughness.harmonic(1e-5, 0.6 / k, 0.6, 16)
    P = np.full(64, 1e5)
    a = C.ReportNormal().half_lengths(P, rough, 0.6, MATERIAL)
    kappa = models.curvature_on_grid(rough, 64, 0.6)
    np.testing.assert_allclose(a, C.hertz_half_length(1e5, 0.46, MATERIAL) * np.sqrt(1 / (1 + 0.46 * kappa)), rtol=1e-12)


def test_the_roughness_slope_is_numpys_periodic_interpolation():
    # the table wrapped once (models._periodic_interpolant) gives numpy.interp(period=...)'s numbers exactly
    period = 2.4
    rough = I.Roughness(np.array([0.0, 2e-6 - 1e-6j, 0.0, 2e-6 + 1e-6j, 0.0]), 1)
    n = 64 * 2
    grid = np.arange(n) * period / n
    values = np.cos(2 * np.pi * 3 * grid / period)
    x = np.linspace(-1.3 * period, 2.7 * period, 10001).reshape(73, 137)
    interpolant = models._periodic_interpolant(grid, values, period)
    assert np.array_equal(interpolant(x), np.interp(x, grid, values, period=period))
    # the table's own points, the period's ends, just below 0, and random points
    edges = np.concatenate((grid, grid - period, [0.0, -0.0, period, -period, -1e-300, np.nextafter(period, 0), 1e-17]))
    rand = np.random.default_rng(4).uniform(-3 * period, 3 * period, 20000)
    for y in (edges, rand):
        assert np.array_equal(interpolant(y), np.interp(y, grid, values, period=period))
    # and the slope is the harmonic's, r' = 2 Re(i beta Z_1 e^{i beta x}), to the interpolation's error
    slope = models.roughness_slope(rough, period)(x)
    beta = 2 * np.pi / period
    exact = np.real(2 * 1j * beta * rough.Z[3] * np.exp(1j * beta * x))
    assert np.max(np.abs(slope - exact)) < 2e-3 * np.max(np.abs(exact))
