"""The study figures as a railway engineer reads them (issue 36): every saved passage count keyed,
a change-in-level view, the 3-D plot against wavelength, readable numbers in titles, a one-speed
growth-rate spectrum as a line, and a missing default comparison stated. Small synthetic datasets
built by the writers the workflow uses (rail.studies.datasets.growth, rate_spectrum_dataset), so
each test takes well under a second of drawing."""

import ast
import importlib.util
import re
from pathlib import Path
from types import SimpleNamespace

import matplotlib.collections
import matplotlib.pyplot as plt
import numpy as np
import pytest

from rail.growth import GrowthHistory
from rail.plotting import report
from rail.plotting import studies as study_plots
from rail.plotting import text
from rail.studies import datasets

ROOT = Path(__file__).resolve().parents[1]
L = 0.6
TRACK = SimpleNamespace(L=L, beta0=2 * np.pi / L, damping="hysteretic", pad=SimpleNamespace(stiffness=3.5e8))


def growth_run(saved=6, smooth=True, K=12, bays=1, step=10_000):
    """A growth dataset with ``saved`` states every ``step`` passages. From a smooth rail the amplitude
    grows linearly, Z(n) = n c; from a rough rail Z(n) = Z0 (1 + n / 50,000): levels whose change is
    known in closed form."""
    J = K * bays
    j = np.arange(1, J + 1)
    c = 1e-11 * np.exp(-j / 5.0) * np.exp(1j * j)  # m per passage, one complex coefficient per line
    n = np.arange(saved) * step
    pos = c[None, :] * (n[:, None] if smooth else (1 + n[:, None] / 50_000) * 1e5)
    Z = np.concatenate([np.conj(pos[:, ::-1]), np.zeros((saved, 1)), pos], axis=1)
    ds = datasets.growth(GrowthHistory(n, Z), TRACK, 40.0, 1, points=41, bays=bays,
                         force=lambda z, x: np.full((1, x.size), 1e5) + 1e12 * z[J + 1].real * np.cos(2 * np.pi * x / L))
    return ds.assign_attrs(normal_contact="report")


@pytest.fixture(autouse=True)
def _close_figures():
    """Each test's figures are closed after it (more than 20 open figures warn, and a warning from
    rail is an error in this suite)."""
    yield
    plt.close("all")


def _texts(fig):
    return [t.get_text() for t in fig.findobj(matplotlib.text.Text)]


# -- the formatting helper ------------------------------------------------------------------------

def test_count_writes_82300_not_an_exponent():
    assert text.count(8.23e4) == "82,300"
    assert text.count(82_345.6) == "82,300"  # a computed interval: three significant figures
    assert text.count(np.int64(82_345)) == "82,345"  # a saved passage count: exact
    assert text.passages(8.23e4) == "82,300 passages" and text.passages(1) == "1 passage"
    for x in np.logspace(0, 10, 41):
        s = text.count(x)
        assert "e+" not in s and "e-" not in s, s
        assert float(s.replace(",", "")) == pytest.approx(x, rel=5e-3)  # 3 significant figures


def test_no_state_is_after_0_passages():
    assert text.after(0) == "initially" and text.after(np.int64(20_000)) == "after 20,000 passages"
    at_start = text.limit_reached(0.0, float("nan"), 31.5)
    assert "after 0" not in at_start and "initially" in at_start and "31.5 mm band" in at_start
    assert text.limit_reached(8.23e4, 95.0, 31.5) == "limit reached after 82,300 passages (95 days) in the 31.5 mm band"


def test_parameter_values_use_powers_of_ten():
    assert text.number(3.5e8) == "3.5×10⁸" and text.number(1e-4) == "10⁻⁴"
    assert text.number(40.0) == "40" and text.number(0.25) == "0.25"


def test_no_plotting_module_formats_passages_with_g_or_int():
    # the helper is used everywhere in plotting: no "{...:.3g} passages" or "{int(...)} passages" left
    for path in (ROOT / "rail/plotting").glob("*.py"):
        src = path.read_text()
        bad = re.findall(r"\{[^{}]*(?::\.?\d*g|int\([^{}]*\))\}\s*passages", src)
        assert not bad, f"{path.name}: {bad}"


# -- the scenario overview ------------------------------------------------------------------------

@pytest.mark.parametrize("smooth", [True, False])
def test_overview_legend_lists_every_saved_passage_count(smooth):
    ds = growth_run(saved=6, smooth=smooth)
    fig = report.scenario_overview(ds, None, "my_pad")
    assert len(fig.legends) == 1
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    assert len(labels) == ds.sizes["passage"] == 6
    assert labels[1:] == ["10,000", "20,000", "30,000", "40,000", "50,000"]
    assert labels[0] == ("0 (smooth: no level)" if smooth else "0")
    # and every state with a level is drawn in panel (a), in its own colour
    lines = [ln for ln in fig.axes[0].get_lines()]
    assert len(lines) == (5 if smooth else 6)
    assert len({tuple(ln.get_color()) for ln in lines}) == len(lines)


def test_overview_with_many_saved_counts_has_a_colour_bar_of_passages():
    fig = report.scenario_overview(growth_run(saved=25, step=4_000), None, "my_pad")
    assert not fig.legends
    bars = [a for a in fig.axes if a.get_ylabel() == "passages"]
    assert len(bars) == 1
    ticks = [t.get_text() for t in bars[0].get_yticklabels()]
    assert ticks[0] == "0" and ticks[-1] == "96,000"


def test_overview_change_in_level_from_a_smooth_rail_is_20log_n_over_n1():
    # linear amplitude growth from a smooth rail: every line's level rises by 20 log10(n / n1)
    ds = growth_run(saved=6, smooth=True)
    change, ref = report.level_change(ds)
    assert ref == 1  # the first state with a level (0 passages has none)
    n = ds["passage"].values
    np.testing.assert_allclose(change[2:], np.broadcast_to(20 * np.log10(n[2:] / n[1])[:, None], change[2:].shape), atol=1e-9)
    fig = report.scenario_overview(ds, None, "my_pad")
    b = fig.axes[1]
    assert b.get_ylabel() == "change in level (dB)" and "since 10,000 passages" in b.get_title()
    drawn = [ln for ln in b.get_lines() if np.size(ln.get_xdata()) > 2]  # the curves, not the reference lines
    assert len(drawn) == 4
    np.testing.assert_allclose(drawn[-1].get_ydata(), 20 * np.log10(5), atol=1e-9)


def test_overview_change_in_level_from_a_rough_rail_is_since_the_start():
    ds = growth_run(saved=6, smooth=False)
    change, ref = report.level_change(ds)
    assert ref == 0
    n = ds["passage"].values
    np.testing.assert_allclose(change, np.broadcast_to(20 * np.log10(1 + n / 50_000)[:, None], change.shape), atol=1e-9)
    assert "since the start" in report.scenario_overview(ds, None, "my_pad").axes[1].get_title()


def test_overview_says_when_there_is_no_default_run():
    ds = growth_run()
    note = "no default run at 45 m/s (the default scenario runs at 20, 40, 60, 80 m/s): no comparison with the default"
    assert note in _texts(report.scenario_overview(ds, None, "x45", note))
    assert any(t.startswith("no default run") for t in _texts(report.scenario_overview(ds, None, "x45")))  # never silent
    assert not any("no default run" in t for t in _texts(report.scenario_overview(ds, None, "default")))
    with_default = report.scenario_overview(ds, growth_run(), "x40")
    assert not any("no default run" in t for t in _texts(with_default))
    assert "default scenario, 50,000 passages" in _texts(with_default)


def _smk_function(name):
    """A helper of workflow/rules/common.smk (plain Python), defined alone against a given config."""
    tree = ast.parse((ROOT / "workflow/rules/common.smk").read_text())
    node = next(n for n in tree.body if isinstance(n, ast.FunctionDef) and n.name == name)
    scope = {"config": {"speeds": [20.0, 40.0, 60.0, 80.0]}}
    exec(compile(ast.Module([node], []), "common.smk", "exec"), scope)
    return scope[name]


def test_workflow_states_the_missing_default_on_the_figure_and_in_the_log(tmp_path, capsys):
    from rail.setup.plan import Plan
    P = SimpleNamespace(config={"speeds": [20.0, 40.0, 60.0, 80.0]})  # the plan's note needs only the speeds
    P.has_default_run = lambda v: Plan.has_default_run(P, v)

    def note(w):
        return Plan.overview_note(P, w.scenario, float(w.speed))

    assert note(SimpleNamespace(scenario="x45", speed="45")).startswith("no default run at 45 m/s (the default scenario runs at 20, 40, 60, 80 m/s)")
    assert note(SimpleNamespace(scenario="x40", speed="40")) == ""  # the default runs there: the comparison is drawn
    assert note(SimpleNamespace(scenario="default", speed="45")) == ""
    # the script writes it to the job's log (stderr) and draws it
    spec = importlib.util.spec_from_file_location("growth_figure", ROOT / "workflow/scripts/growth_figure.py")
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    run = tmp_path / "V45.nc"
    growth_run().to_netcdf(run)
    inputs = SimpleNamespace(run=str(run), keys=lambda: ["run"])
    script.main("scenario_overview", "x45", inputs, [str(tmp_path / "o.png")], {"default_note": note(SimpleNamespace(scenario="x45", speed="45"))})
    assert "x45: no default run at 45 m/s" in capsys.readouterr().err
    assert (tmp_path / "o.png").stat().st_size > 10_000


# -- the 3-D plot ---------------------------------------------------------------------------------

def test_scenario_3d_plot_is_against_wavelength_in_mm():
    ds = growth_run(K=24)
    fig = report.growth_3d(ds, "wavelength", "my_pad")
    ax = fig.axes[0]
    assert ax.get_xlabel() == "wavelength (mm, log scale)"
    lam_mm = 2 * np.pi / ds["wavenumber"].values * 1e3  # 600 mm to 25 mm
    ticks = [float(t.get_text()) for t in ax.get_xticklabels()]
    np.testing.assert_allclose(ax.get_xticks(), np.log10(ticks))  # log axis, labelled in mm
    assert min(ticks) >= lam_mm.min() and max(ticks) <= lam_mm.max() and 100.0 in ticks
    assert "my_pad" in ax.get_title()


def test_default_3d_plot_follows_the_report_against_wavenumber():
    ax = report.growth_3d(growth_run()).axes[0]
    assert ax.get_xlabel() == "wavenumber (rad/m)"
    assert _smk_function("growth_3d_axis")(SimpleNamespace(scenario="default")) == "wavenumber"
    assert _smk_function("growth_3d_axis")(SimpleNamespace(scenario="my_pad")) == "wavelength"
    with pytest.raises(ValueError, match=r"axis = 'frequency' is not allowed: it must be 'wavenumber' or 'wavelength'"):
        report.growth_3d(growth_run(), "frequency")


# -- the growth-rate spectrum of one speed ----------------------------------------------------------

def _rate_spectrum(speeds):
    from rail.growth_spectrum import RateSpectrum
    from rail.studies.rate_spectrum import rate_spectrum_dataset

    lines = np.arange(24, 61, 4)
    spectra = {}
    for v in speeds:
        rate = (np.linspace(-1, 1, lines.size) * 1e-7 * v / 40).astype(complex)
        spectra[v] = RateSpectrum(4 * 0.6 / lines, lines, (lines % 4 == 0).astype(int), rate, rate, np.zeros(lines.size),
                                  np.zeros(lines.size), np.zeros(lines.size), 1e-4, 1e-9, 4, 1)
    return rate_spectrum_dataset(spectra, 0.6, 1)


def _meshes(fig):
    return [c for ax in fig.axes for c in ax.collections if isinstance(c, matplotlib.collections.QuadMesh)]


def test_one_speed_spectrum_is_a_line_not_a_map():
    ds = _rate_spectrum([50.0])
    fig = study_plots.rate_spectrum_figure(ds)
    assert not _meshes(fig)
    assert len(fig.axes) == 1
    ax = fig.axes[0]
    assert ax.get_xlabel() == "wavelength (mm)" and "at 50 m/s" in ax.get_title()
    line = [ln for ln in ax.get_lines() if np.size(ln.get_xdata()) == ds.sizes["wavelength"]]
    assert len(line) == 1
    np.testing.assert_allclose(line[0].get_ydata(), ds["growth_dB_per_1e5_axles"].values[0])
    assert ax.get_ylabel() == "growth (dB per 100,000 axle passages)"


def test_two_speed_spectrum_keeps_its_map():
    fig = study_plots.rate_spectrum_figure(_rate_spectrum([40.0, 50.0]))
    assert any(isinstance(c, matplotlib.collections.QuadMesh) for c in fig.axes[1].collections)  # the map (its colour bar has one too)
    assert fig.axes[1].get_ylabel() == "speed (m/s)"
