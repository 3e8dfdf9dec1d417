"""The wheels' roughness as a source of rail roughness (issue 58; rail.growth_spectrum.source,
rail.studies.wheel_source): the expected-spectrum recursion against its own iteration and its small-rate
limit Q / (-2 g), the line powers against their band, the source's linearity and phase independence in the
nonlinear passage, and (slow) an ensemble of nonlinear passages with random wheel phases against the
expected spectrum."""

import dataclasses
import re

import numpy as np
import pytest
from model import scenario
from test_growth import MATERIAL, contact_spring, track

from rail import chain, moving
from rail import growth_spectrum as GS
from rail.bands import wavelength_bands
from rail.growth_spectrum import source as src
from rail.studies import wheel_source as ws

K, N = 24, 4
SPEED = 40.0


def test_expected_mean_square_is_the_recursion_it_solves():
    # S_{n+1} = abs(1 - R)^2 S_n + Q and c_{n+1} = (1 - R) c_n + s iterated by hand, lines that decay, grow and hold
    rng = np.random.default_rng(5)
    R = np.array([0.02 + 0.01j, -0.01 + 0.03j, 0.0 + 0.0j, 1e-7 - 2e-6j, 0.3 - 0.2j])
    Q = rng.uniform(0.5, 2.0, R.size) * 1e-14
    S0 = rng.uniform(0.5, 2.0, R.size) * 1e-12
    s = np.array([0.0, 2e-9, 1e-9, 3e-10, 0.0])
    S, c = S0.copy(), np.zeros(R.size, dtype=complex)
    for n in range(0, 301):
        got = src.expected_mean_square(n, S0, R, Q, comb=s)
        want = S + np.abs(c) ** 2 / 2
        assert np.allclose(got, want, rtol=1e-10, atol=0), n
        S = np.abs(1 - R) ** 2 * S + Q
        c = (1 - R) * c + s


def test_a_decaying_line_settles_at_Q_over_minus_2g_in_the_small_rate_limit():
    # the equation dS/dn = 2 g S + Q: S_inf = Q / (-2 g) as the rate per passage goes to zero (relative
    # difference abs(R)^2 / (2 g) from the discrete step: first order in the rate), and the recursion reaches it
    Q = 1e-16
    for g in (-1e-3, -1e-5, -1e-7):
        R = -g + 0.5j * abs(g)  # growth rate g < 0: decays; a drift as large as half the rate
        S_inf = src.settled_mean_square(R, Q)
        assert abs(S_inf / (Q / (-2 * g)) - 1) < 2 * abs(R) ** 2 / abs(2 * g) + 1e-12
        n = src.passages_to_settle(R, 1.0)
        assert 10 * np.log10(S_inf / src.expected_mean_square(n, 0.0, R, Q)) == pytest.approx(1.0, abs=1e-6)
    assert np.isinf(src.settled_mean_square(-1e-4, Q))  # growing: no settled level
    assert np.isinf(src.passages_to_settle(-1e-4))


def test_the_lines_of_a_period_inside_a_band_hold_its_mean_square():
    # a band's density spread evenly over its wavenumbers: the lines 2 pi j / (N L) inside the band sum to its mean
    # square, to within one line's share (the count of lines in a band is whole); and back from the lines exactly
    bands = wavelength_bands(0.2, 0.02)
    levels = np.linspace(5.0, -10.0, bands.centre.size)
    for period in (64 * 0.6, 256 * 0.6):
        j = np.arange(1, int(period / 0.015))
        lam = period / j
        P = src.wheel_line_power(lam, period, bands.centre, levels)
        share, band = src.line_share(lam, period, bands.centre)
        for b in range(bands.centre.size):
            sel = band == b
            ms = 1e-12 * 10 ** (levels[b] / 10)
            assert abs(P[sel].sum() / ms - 1) <= share[sel].max() * (1 + 1e-9)
        back = src.band_mean_square_from_lines(P, share, band, bands.centre.size)
        assert np.allclose(10 * np.log10(back / 1e-12), levels, atol=1e-9)


def test_bad_wheel_spectra_and_train_sizes_are_refused():
    bands = wavelength_bands(0.2, 0.02)
    with pytest.raises(ValueError, match="level_dB"):
        src.wheel_line_power([0.05], 2.4, bands.centre, np.full(bands.centre.size, np.nan))
    with pytest.raises(ValueError, match="period"):
        src.line_share([0.05], float("inf"), bands.centre)
    with pytest.raises(ValueError, match="wheels"):
        src.source_power([1e-5], [1e-12], 0)
    with pytest.raises(ValueError, match="disc"):
        ws.named_spectrum("drum")


@pytest.fixture(scope="module")
def setup():
    tr = track()
    scn = scenario(tr, MATERIAL, contact_spring(), K=K, nodes=41, passages=100000, step=10000)
    scn = dataclasses.replace(scn, roughness=dataclasses.replace(scn.roughness, bays=N))
    return scn, moving.bloch_tables(tr, SPEED, K, N)


def _wheel(Z_len, j, amplitude, phase):
    """A wheel roughness at line j of the period: amplitude [m] (its line's mean square amplitude^2 / 2), phase [rad]."""
    J = (Z_len - 1) // 2
    W = np.zeros(Z_len, dtype=complex)
    W[J + j] = amplitude / 2 * np.exp(1j * phase)
    W[J - j] = np.conj(W[J + j])
    return W


def _rough_wheel_wear(scn, tabs, Zrail, W):
    """The rail's change by one passage of a rough wheel (one wheel: it sees the rail's roughness and its own)."""
    dZ, _ = chain.train_wear(scn, tabs, Zrail + W)
    return -dZ


def test_a_rough_wheel_wears_the_rail_as_the_linear_source_says_linear_in_its_amplitude_whatever_its_phase(setup):
    # one rough-wheel passage over the smooth rail at a free line of the 4-bay period (j = 37, 64.9 mm and j = 86,
    # 27.9 mm): the rail's change at the line, less the smooth rail's (nothing at a free line), is -R W with R the
    # spectrum's rate (the same chain: the wheel's roughness and the rail's enter the contact as one); twice the wheel
    # roughness gives four times the mean square Q = abs(R)^2 P, and a wheel of another phase the same Q
    scn, tabs = setup
    J = N * K
    Z0 = np.zeros(2 * J + 1, dtype=complex)
    smooth = _rough_wheel_wear(scn, tabs, Z0, 0 * Z0)
    lines = [37, 86]
    R = GS.rate_spectrum(scn, tabs, lines, grid_phases=1, check_lines=1, method="linear").rate
    for j, r in zip(lines, R):
        assert abs(smooth[J + j]) < 1e-3 * abs(r) * 1e-7 / 2  # a free line: no comb (against the wheel's own below)
        q = {}
        for amp in (1e-7, 2e-7):
            for phase in (0.0, 1.3, 4.0):
                W = _wheel(Z0.size, j, amp, phase)
                d = _rough_wheel_wear(scn, tabs, Z0, W)[J + j] - smooth[J + j]
                # -R W against the nonlinear passage: the linear method's agreement with the probes (test_growth_spectrum)
                assert abs(d / (-r * W[J + j]) - 1) < 3e-3, (j, amp, phase)
                q[(amp, phase)] = 2 * abs(d) ** 2
        for phase in (1.3, 4.0):
            assert q[(1e-7, phase)] / q[(1e-7, 0.0)] == pytest.approx(1.0, abs=5e-3)
        assert q[(2e-7, 0.0)] / q[(1e-7, 0.0)] == pytest.approx(4.0, rel=5e-3)
        assert q[(1e-7, 0.0)] == pytest.approx(src.source_power(r, (1e-7) ** 2 / 2, 1), rel=6e-3)


@pytest.mark.slow
def test_an_ensemble_of_random_wheel_phases_follows_the_expected_spectrum(setup):
    # 64 members, each 30 passages of a rough wheel of random phase over a rail that starts smooth, the wear coefficient
    # scaled by 2e4 so that the decaying line (j = 86, 27.9 mm: R about 3.6 % per passage here) comes within 1 dB of its
    # settled level in the run; the ensemble's mean square at the line against S_n = Q (1 - a^n) / (1 - a) of the linear
    # R, within three standard errors at every passage. After the first passage every member holds the same mean square
    # (the wheel's amplitude is given, only its phase is random): no sampling error there, and the difference is the
    # linearisation's (8e-5 of it, measured), inside the single passage's 3e-3 of the test above. (Measured, 40 passages:
    # every passage after the first within 1.0 standard errors; 6 min of CPU.)
    scn, tabs = setup
    scale = 2e4
    scn = dataclasses.replace(scn, wear_law=dataclasses.replace(scn.wear_law, coefficient=scn.wear_law.coefficient * scale))
    j, amp = 86, 1e-7
    r = GS.rate_spectrum(scn, tabs, [j], grid_phases=1, check_lines=1, method="linear").rate[0]
    assert 0.01 < r.real < 0.2  # decays, fast enough to settle in the run
    J = N * K
    rng = np.random.default_rng(58)
    members, passages = 64, 30
    ms = np.zeros((members, passages + 1))
    for m in range(members):
        Z = np.zeros(2 * J + 1, dtype=complex)
        for n in range(passages):
            W = _wheel(Z.size, j, amp, rng.uniform(0, 2 * np.pi))
            Z = Z + _rough_wheel_wear(scn, tabs, Z, W)
            ms[m, n + 1] = 2 * abs(Z[J + j]) ** 2
    Q = src.source_power(r, amp**2 / 2, 1)
    want = src.expected_mean_square(np.arange(passages + 1), 0.0, r, Q)
    mean, se = ms.mean(axis=0), ms.std(axis=0, ddof=1) / np.sqrt(members)
    assert np.all(np.abs(mean[1:] - want[1:]) <= 3 * se[1:] + 3e-3 * want[1:]), np.round((mean - want) / np.maximum(se, 1e-300), 1)
    assert np.all(se[2:] > 1e-3 * want[2:])  # the phases are random: the members spread
    assert want[-1] > 10 ** (-1 / 10) * src.settled_mean_square(r, Q)  # within 1 dB of the settled level by the end


def test_without_a_wheel_source_the_spectrum_is_the_dataset_itself():
    # wheel_source.roughness none (the default): with_wheel_source hands back the very dataset, untouched (bit for bit
    # every result as before the source existed), and the resolved configuration says none
    import xarray as xr

    from rail.app import api
    from rail.setup import inputs

    st = api.load("default")
    assert (st.config.get("wheel_source") or {}).get("roughness", "none") == "none"  # the section is optional
    assert inputs.wheel_source_spectra(st.config) is None
    ds = xr.Dataset({"x": ("wavelength", np.arange(3.0))})
    assert ws.with_wheel_source(ds, None, None, {}, None) is ds


@pytest.mark.parametrize("text, message", [
    ("wheel_source:\n  roughness: file\n", r"wheel_source\.roughness = 'file' needs wheel_source\.file"),
    ("wheel_source:\n  roughness: file\n  file: nowhere.csv\n", r"wheel_source\.file: .*nowhere\.csv"),
    ("wheel_source:\n  roughness: disc\n  ground: file\n", r"wheel_source\.ground = 'file' needs wheel_source\.ground_file"),
    ("wheel_source:\n  roughness: disc\n  ground: file\n  ground_file: nowhere.csv\n", r"wheel_source\.ground_file: .*nowhere\.csv"),
    ("wheel_source:\n  roughness: drum\n", r"wheel_source\.roughness = 'drum' is not allowed"),
])
def test_check_refuses_a_bad_wheel_source_before_computing(tmp_path, capsys, text, message):
    from rail.app import cli

    scen = tmp_path / "mine.yaml"
    scen.write_text(text)
    assert cli.main(["check", str(scen)]) == 2
    err = capsys.readouterr().err.strip()
    assert "Traceback" not in err and re.search(message, err), err


def test_a_wheel_spectrum_file_is_read_with_the_rail_spectrums_checks(tmp_path, capsys):
    from rail.app import cli

    bad = tmp_path / "wheel.csv"
    bad.write_text("wavelength_m,level_dB\n0.1,2.0\n0.08,1e6\n")
    scen = tmp_path / "mine.yaml"
    scen.write_text(f"wheel_source:\n  roughness: file\n  file: {bad}\n")
    assert cli.main(["check", str(scen)]) == 2
    err = capsys.readouterr().err
    assert re.search(r"wheel_source\.file: .*wheel\.csv, line 3: level 1e\+06 dB re 1 µm is not allowed", err), err


def test_a_study_file_that_builds_settled_asks_for_the_settled_spectrum(root):
    from rail.setup.config import load_yaml, validate_config
    from rail.setup.plan import plan

    schema = load_yaml(root / "config/schema/config.schema.yaml")
    p = plan(validate_config(load_yaml(root / "config/config.yaml"), schema), schema, root=root)
    targets = p.study_file_targets("wheel_source")
    for case in ("ws_disc", "ws_cast_iron", "ws_rail_cast_iron"):
        assert f"results/spectrum/{case}/settled.png" in targets
        assert p.scenarios[case]["wheel_source"]["roughness"] in ("disc", "cast_iron")


def test_the_source_dataset_states_its_model_and_refuses_a_train_without_its_wheels_own_rate():
    # a hand-made spectrum of two lines on a 2-bay period: one decays (its settled level Q / (1 - a)), one grows (none)
    import xarray as xr

    L = 0.6
    lam = np.array([2 * L / 20, 2 * L / 30])
    ds = xr.Dataset({"growth_rate": (("speed", "wavelength"), [[-1e-5, 2e-5]]), "drift": (("speed", "wavelength"), [[3e-6, 0.0]]),
                     "source": (("speed", "wavelength"), [[0.0, 0.0]])},
                    coords={"speed": [40.0], "wavelength": lam, "line": ("wavelength", [20, 30]),
                            "frequency": (("speed", "wavelength"), 40.0 / lam[None, :])},
                    attrs={"wheels": 1, "bays": 2, "sleeper_spacing_m": L})
    out = ws.source_dataset(ds, ws.named_spectrum("cast_iron"), ground=ws.named_spectrum("E", "rail"),
                            limit=ws.named_spectrum("M", "rail"))
    R = -(ds.growth_rate.values[0] + 1j * ds.drift.values[0])
    P = src.wheel_line_power(lam, 2 * L, ws.named_spectrum("cast_iron").centres, ws.named_spectrum("cast_iron").levels)
    S = np.abs(R[0]) ** 2 * P[0] / (1 - abs(1 - R[0]) ** 2)
    assert out.settled_level_dB.values[0, 0] == pytest.approx(10 * np.log10(S / 1e-12), abs=1e-9)
    assert np.isposinf(out.settled_level_dB.values[0, 1])
    assert "S_{n+1}" in out.attrs["wheel_source_model"]
    text = ws.settled_csv_text(out)
    assert text.startswith("# expected rail roughness") and "speed_m_s,band_nominal_m,wheel_dB_re_1um,settled_dB_re_1um" in text
    assert "inf" in text  # the growing line's band
    two = ds.assign_attrs(wheels=2)
    with pytest.raises(ValueError, match="rate_own: a train of 2 wheels"):
        ws.source_dataset(two, ws.named_spectrum("disc"))
