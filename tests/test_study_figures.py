"""The study figures as a railway engineer reads them (issue 36): every saved passage count keyed,
a change-in-level view, the 3-D plot against wavelength, readable numbers in titles, a one-speed
growth-rate spectrum as a line, and a missing default comparison stated. Small synthetic datasets
built by the writers the workflow uses (rail.studies.datasets.growth, rate_spectrum_dataset), so
each test takes well under a second of drawing."""

import ast
import dataclasses
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
    key = [leg for leg in fig.legends if leg.get_title().get_text() == "passages"]  # the other: the notes below the panels
    assert len(key) == 1
    labels = [t.get_text() for t in key[0].get_texts()]
    assert len(labels) == ds.sizes["passage"] == 6
    assert labels[1:] == ["10,000", "20,000", "30,000", "40,000", "50,000"]
    assert labels[0] == ("0 (smooth: no level)" if smooth else "0")
    # and every state with a level is drawn in panel (a), in its own colour
    lines = [ln for ln in fig.axes[0].get_lines()]
    assert len(lines) == (5 if smooth else 6)
    assert len({tuple(ln.get_color()) for ln in lines}) == len(lines)


def test_overview_with_many_saved_counts_has_a_colour_bar_of_passages():
    fig = report.scenario_overview(growth_run(saved=25, step=4_000), None, "my_pad")
    assert not [leg for leg in fig.legends if leg.get_title().get_text() == "passages"]
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


# -- figures a practitioner shows a colleague (issue 45, item 4) -------------------------------------

def _bands(saved=6, smooth=True, traffic=None):
    """The band view's dataset of a growth run (rail.studies.bands.bands_dataset, as the workflow builds it)."""
    from rail.studies.bands import bands_dataset, third_octave_bands

    g = growth_run(saved=saved, smooth=smooth, K=24)
    return bands_dataset(g, L, third_octave_bands(), 1, per_day=20_000.0, traffic=traffic)


def _rate_spectrum_with_traffic(speeds):
    from rail.growth_spectrum import RateSpectrum
    from rail.studies.rate_spectrum import rate_spectrum_dataset
    from rail.traffic import Traffic

    lines = np.arange(24, 61, 4)
    spectra = {v: RateSpectrum(4 * 0.6 / lines, lines, (lines % 4 == 0).astype(int), np.linspace(-1, 1, lines.size) * 1e-7 + 0j,
                               np.linspace(-1, 1, lines.size) * 1e-7 + 0j, np.zeros(lines.size), np.zeros(lines.size),
                               np.zeros(lines.size), 1e-4, 1e-9, 4, 1) for v in speeds}
    return rate_spectrum_dataset(spectra, 0.6, 1, traffic=Traffic(20_000.0, 22.5))


def _study_figures():
    """Every study figure of a growth run and a growth-rate spectrum, drawn from small synthetic datasets,
    with the notes they can carry (a missing default, the wear path)."""
    from rail.traffic import Traffic

    run = growth_run(saved=6, smooth=True, K=24, bays=2).assign_attrs(wear_path="patch", contact_shift_modelled=1)
    note = "no default run at 45 m/s (the default scenario runs at 20, 40, 60, 80 m/s): no comparison with the default"
    return {
        "overview, no default": report.scenario_overview(run, None, "x45", note),
        "overview, default": report.scenario_overview(run, growth_run(), "x40", "", [(0.0, ""), (0.6, "ballast ×0.001"), (1.2, "")]),
        "3-D": report.growth_3d(run, "wavelength", "x45"),
        "narrow band": report.growth_narrowband(run),
        "bands": report.band_spectra(_bands(traffic=Traffic(20_000.0, 22.5)).assign_attrs(wear_path="patch", contact_shift_modelled=1)),
        "spectrum, one speed": study_plots.rate_spectrum_figure(_rate_spectrum_with_traffic([50.0])),
        "spectrum, two speeds": study_plots.rate_spectrum_figure(_rate_spectrum_with_traffic([40.0, 50.0])),
    }


def _text_boxes(fig):
    """(what, window extent) of every piece of text a reader reads as a unit: the figure's title and
    legends, and each axes' titles, axis labels and legend (secondary axes included)."""
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    out = []
    if fig._suptitle is not None and fig._suptitle.get_text():
        out.append(("suptitle", fig._suptitle.get_window_extent(r)))
    for i, leg in enumerate(fig.legends):
        out.append((f"figure legend {i} ({leg.get_gid()})", leg.get_window_extent(r)))
    out += [(f"figure text {t.get_text()[:30]!r}", t.get_window_extent(r)) for t in fig.texts
            if t.get_text() and t is not fig._suptitle]
    for k, ax in enumerate(fig.axes):
        axes = [ax] + list(ax.child_axes)
        for j, a in enumerate(axes):
            name = f"axes {k}" + (f" secondary {j}" if j else "")
            for loc in ("left", "center", "right") if not j else ():
                t = a.get_title(loc)
                if t:
                    out.append((f"{name} title {t[:30]!r}", a.title.get_window_extent(r) if loc == "center" else
                                (a._left_title if loc == "left" else a._right_title).get_window_extent(r)))
            if hasattr(a, "zaxis"):
                continue  # a 3-D axes' labels sit on its box, projected; checked against the title below
            for axis in (a.xaxis, a.yaxis):
                if axis.label.get_text() and axis.label.get_visible():
                    out.append((f"{name} label {axis.label.get_text()[:30]!r}", axis.label.get_window_extent(r)))
            if a.get_legend() is not None:
                out.append((f"{name} legend", a.get_legend().get_window_extent(r)))
    return out


@pytest.mark.parametrize("which", ["overview, no default", "overview, default", "3-D", "narrow band", "bands",
                                   "spectrum, one speed", "spectrum, two speeds"])
def test_no_text_of_a_study_figure_covers_another_or_a_curve(which):
    fig = _study_figures()[which]
    boxes = _text_boxes(fig)
    clash = [(a, b) for i, (a, ba) in enumerate(boxes) for b, bb in boxes[i + 1:] if ba.overlaps(bb)]
    assert not clash, clash
    # the notes (a missing default, the wear path) sit outside every axes: they cover no curve
    r = fig.canvas.get_renderer()
    assert not [t for t in fig.texts if t is not fig._suptitle]  # a note placed by hand in figure coordinates is not kept off the axes by the layout
    notes = [leg for leg in fig.legends if leg.get_gid() == "notes"]
    assert which.startswith("3-D") or notes  # every figure here carries the wear-path note
    for leg in notes:
        for ax in fig.axes:
            assert not leg.get_window_extent(r).overlaps(ax.get_window_extent(r)), ax.get_title()


def test_missing_default_is_a_note_below_the_panels_not_over_the_curves():
    fig = _study_figures()["overview, no default"]
    notes = [leg for leg in fig.legends if leg.get_gid() == "notes"]
    assert len(notes) == 1
    texts = [t.get_text() for t in notes[0].get_texts()]
    assert texts[0].startswith("no default run at 45 m/s") and "true path" in texts[-1]
    assert matplotlib.colors.to_hex(notes[0].get_texts()[0].get_color()) == matplotlib.colors.to_hex("firebrick")
    assert not any("no default run" in t.get_text() for ax in fig.axes for t in ax.texts)  # nothing inside a panel


def test_every_wavelength_axis_decreases_to_the_right():
    # one direction everywhere, as EN 15610 roughness spectra and the report's wavenumber axes run
    checked = 0
    for name, fig in _study_figures().items():
        for ax in fig.axes:
            if "wavelength" in ax.get_xlabel():
                lo, hi = ax.get_xlim()
                assert lo > hi, f"{name}: {ax.get_xlabel()} runs from {lo:g} to {hi:g}"
                checked += 1
    assert checked >= 10


def _secondary(ax, which):
    return [a for a in ax.child_axes if (a.get_xlabel() if which == "x" else a.get_ylabel())]


def test_spectrum_has_a_frequency_axis_at_its_speed_and_a_per_MGT_axis():
    fig = _study_figures()["spectrum, one speed"]
    fig.canvas.draw()  # a secondary axis takes its limits from its parent's when drawn
    ax = fig.axes[0]
    top, = _secondary(ax, "x")
    assert top.get_xlabel() == "frequency at V = 50 m/s (Hz)"
    # f = V / lambda: 1000 Hz sits above 50 mm at 50 m/s, 2000 Hz above 25 mm
    for f, lam_mm in ((1000.0, 50.0), (2000.0, 25.0)):
        assert top.transData.transform((f, 0))[0] == pytest.approx(ax.transData.transform((lam_mm, 0))[0], abs=1e-6)
    right, = _secondary(ax, "y")
    assert right.get_ylabel() == "dB per MGT (axle load 22.5 t)"
    # 1 dB per 100,000 axles of 22.5 t is 1e6 / 22.5 / 1e5 = 0.444 dB per MGT
    assert right.transData.transform((0, 1e6 / 22.5 / 1e5))[1] == pytest.approx(ax.transData.transform((0, 1.0))[1], abs=1e-6)
    # two speeds: no one frequency, the per-MGT axis stays
    two = _study_figures()["spectrum, two speeds"].axes[0]
    assert not _secondary(two, "x") and _secondary(two, "y")[0].get_ylabel() == "dB per MGT (axle load 22.5 t)"


def test_band_view_has_frequency_axes_and_its_level_rate_a_per_MGT_axis():
    fig = _study_figures()["bands"]
    a1, a2, a3 = fig.axes[:3]
    for ax in (a1, a2, a3):
        assert [s.get_xlabel() for s in _secondary(ax, "x")] == ["frequency at V = 40 m/s (Hz)"]
    assert [s.get_ylabel() for s in _secondary(a2, "y")] == ["dB per MGT (axle load 22.5 t)"]
    assert not _secondary(a3, "y")  # µm per 100,000 axles has no dB per MGT


def test_band_view_keys_every_save_with_a_level_each_in_its_own_colour_and_marker():
    ds = _bands(saved=6, smooth=True)
    fig = report.band_spectra(ds)
    with_level = np.isfinite(ds["level"].values[:, ds["resolved"].values.astype(bool)]).any(axis=1)
    assert with_level.sum() == 5  # the smooth rail at 0 passages has no level
    key, = [leg for leg in fig.legends if leg.get_gid() != "notes"]
    labels = [t.get_text() for t in key.get_texts()]
    saves = [lab for lab in labels if lab[0].isdigit()]
    assert saves == ["10,000 (0.5 days)", "20,000 (1 day)", "30,000 (1.5 days)", "40,000 (2 days)", "50,000 (2.5 days)"]
    lines = [ln for ln in fig.axes[0].get_lines() if ln.get_label() in saves]
    assert len(lines) == 5
    assert len({matplotlib.colors.to_hex(ln.get_color()) for ln in lines}) == 5
    assert len({ln.get_marker() for ln in lines}) == 5
    assert {"linear growth fits better", "exponential growth fits better"} <= set(labels)  # one key for the figure


def test_narrow_band_view_keys_its_saves_in_colours_and_line_styles_alike():
    fig = report.growth_narrowband(growth_run(saved=6, bays=2))
    for ax in fig.axes[:2]:
        lines = [ln for ln in ax.get_lines() if ln.get_label().endswith("passages")]
        assert [ln.get_label() for ln in lines] == ["0 passages", "30,000 passages", "50,000 passages"]  # first, middle, last
        assert len({matplotlib.colors.to_hex(ln.get_color()) for ln in lines}) == 3
        assert len({ln.get_linestyle() for ln in lines}) == 3


def _jump_run():
    """A rough rail whose spectrum jumps by 60 dB between two neighbouring lines and grows by 6 dB."""
    ds = growth_run(saved=6, smooth=False, K=24)
    level = ds["level"].values.copy()
    level[:, ds["harmonic"].values > 8] -= 60.0
    return ds.assign(level=(ds["level"].dims, level, ds["level"].attrs))


def test_3d_plot_height_is_the_growth_not_a_jump_in_the_spectrum():
    ds = _jump_run()
    ax = report.growth_3d(ds, "wavelength", "jump").axes[0]
    lo, hi = ax.get_zlim()
    assert hi - lo < 15.0  # the growth, 20 log10(2) = 6 dB, fills the height, not the 60 dB jump
    assert "change" in ax.get_zlabel() and "dB" in ax.get_zlabel()
    lo, hi = ax.get_xlim()
    assert lo > hi  # long wavelengths on the left, as the other study figures
    # the default scenario's section-5 plot stays the report's level over wavenumber
    ax = report.growth_3d(ds).axes[0]
    assert ax.get_zlabel() == "level (dB re 1 µm)" and ax.get_zlim()[1] - ax.get_zlim()[0] > 60


def _support_lines(ax, gid):
    return sorted(float(ln.get_xdata()[0]) for ln in ax.get_lines() if ln.get_gid() == gid)


def test_sleepers_are_marked_along_the_rail_at_the_support_positions():
    ds = growth_run(saved=3, bays=2)
    fig = report.scenario_overview(ds, None, "x")
    for ax in (fig.axes[2], fig.axes[3]):  # (c) profile, (d) force
        assert _support_lines(ax, "support") == pytest.approx([0.0, L, 2 * L])
        assert "dotted: sleepers" in ax.get_xlabel()
    assert _support_lines(report.growth_narrowband(ds).axes[1], "support") == pytest.approx([0.0, L, 2 * L])


def test_a_voided_support_is_marked_and_described_where_the_cell_has_it():
    from rail.cell import make_cell
    from rail.setup import build
    from rail.setup.config import project_schema, resolve, load_yaml
    from rail.studies.irregular import support_marks

    from rail.setup.study_files import study_cases

    cfg = resolve(load_yaml(ROOT / "config/config.yaml"), project_schema(), study_cases(ROOT)["irregular_voided"][1])
    cell = build.track_cell(cfg)
    marks = support_marks(cell)
    assert marks == [(0.0, ""), (pytest.approx(0.6), "ballast ×0.001"), (pytest.approx(1.2), ""), (pytest.approx(1.8), ""),
                     (pytest.approx(2.4), "")]
    assert support_marks(make_cell(cell.track, 2, pad=[1.0, 2.0]))[1][1] == "pad ×2"
    fig = report.scenario_overview(growth_run(saved=3, bays=4), None, "irregular_voided", "", marks)
    for ax in (fig.axes[2], fig.axes[3]):
        assert _support_lines(ax, "support-differs") == pytest.approx([0.6])
        assert _support_lines(ax, "support") == pytest.approx([0.0, 1.2, 1.8, 2.4])
        assert "red dashed: ballast ×0.001 at 0.6 m" in ax.get_xlabel()


def test_the_overview_script_reads_the_cell_from_the_runs_configuration():
    import yaml
    from rail.setup.config import project_schema, resolve, load_yaml

    spec = importlib.util.spec_from_file_location("growth_figure", ROOT / "workflow/scripts/growth_figure.py")
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    defaults = load_yaml(ROOT / "config/config.yaml")
    from rail.setup.study_files import study_cases

    voided = resolve(defaults, project_schema(), study_cases(ROOT)["irregular_voided"][1])  # config/studies/irregular_track.yaml
    run = growth_run(saved=2, bays=4)
    assert [m[1] for m in script.supports(run.assign_attrs(config=yaml.safe_dump(voided)))][1] == "ballast ×0.001"
    assert script.supports(run.assign_attrs(config=yaml.safe_dump(resolve(defaults, project_schema())))) is None  # uniform: the figure's own
    assert script.supports(run) is None


# -- the model choices every figure's data states (issue 57, item 8) -----------------------------

def _script(name):
    spec = importlib.util.spec_from_file_location(name, ROOT / f"workflow/scripts/{name}.py")
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    return script


def test_every_report_growth_figures_data_states_its_wear_path_and_normal_contact_as_values(tmp_path):
    # results/data/fig23.nc did not state its wear path although the README says every figure does
    import xarray as xr

    from rail.setup.config import load_yaml
    from rail.studies.validity import model_attributes

    config = load_yaml(ROOT / "config/config.yaml")
    patch, wheel = tmp_path / "patch.nc", tmp_path / "wheel.nc"
    growth_run(K=24).assign_attrs(model_attributes("patch", "nonhertzian")).to_netcdf(patch)
    growth_run(K=24).assign_attrs(model_attributes("wheel", "report")).to_netcdf(wheel)
    runs = {"20": {"one run": str(patch)}, "23": {"V40": str(patch), "V60": str(patch)}, "24": {"patch": str(patch), "wheel": str(wheel)}}
    data = [tmp_path / f"fig{nn}.nc" for nn in runs]
    _script("growth_figure").report_figures(runs, config, data, [tmp_path / f"fig{nn}.png" for nn in runs])
    with xr.open_dataset(data[0]) as ds20, xr.open_dataset(data[1]) as ds23, xr.open_dataset(data[2]) as ds24:
        for ds in (ds20, ds23):  # runs of one wear path: stated as values
            assert (ds.attrs["wear_path"], ds.attrs["normal_contact"]) == ("patch", "nonhertzian")
            assert ds.attrs["wear_path_description"].startswith("patch: the wear where the contact patch is")
        assert ds24.attrs["wear_path"].startswith("mixed")  # two runs of two paths: each variable says its own
        assert {(v.attrs["wear_path"], v.attrs["normal_contact"]) for v in ds24.data_vars.values()} == {("patch", "nonhertzian"),
                                                                                                       ("wheel", "report")}


def test_a_figures_data_without_its_model_choices_is_refused_and_the_radiation_figures_say_none(tmp_path, steel):
    import xarray as xr

    from rail import halfspace
    from rail.setup import build, io
    from rail.setup.config import load_yaml

    config = load_yaml(ROOT / "config/config.yaml")
    bare = xr.Dataset({"x": ("i", [1.0], {"units": "1", "long_name": "x"})})
    with pytest.raises(ValueError, match=r"dataset 'Figure 7' does not state its wear_path and normal_contact"):
        io.finalize(bare, config, title="Figure 7", source="test")
    io.finalize(bare, config, title="Roughness growth", source="test")  # a result that is not a figure's data: no demand
    s = build.halfspace_figures(config)
    small = build.HalfSpaceFigureSettings(s.frequency, s.radius, s.radii[:3], s.frequencies[:3], s.hertz_stiffness)
    rad = tmp_path / "radiation.nc"
    datasets.radiation(steel, small, halfspace.HalfSpaceNumerics(epsrel=1e-6)).to_netcdf(rad)
    data = [tmp_path / "fig05.nc", tmp_path / "fig06.nc"]
    _script("radiation_figure").main(["05", "06"], config, rad, data, [tmp_path / "fig05.png", tmp_path / "fig06.png"])
    for path in data:
        with xr.open_dataset(path) as ds:
            assert (ds.attrs["wear_path"], ds.attrs["normal_contact"]) == ("none", "none")


def test_integer_like_attributes_are_written_as_integers(tmp_path):
    # a fleet's growth file said wheels = 3.9999999999999996
    import xarray as xr

    from rail import fleet as F
    from rail.setup import io
    from rail.setup.config import load_yaml
    from rail.studies.validity import model_attributes

    ds = xr.Dataset({"x": ("i", [1.0], {"units": "1", "long_name": "x"})}, attrs={
        "wheels": 3.9999999999999996, "speed_m_per_s": 40.0, "axles_per_train": 3.4, "eps_m": 1e-9, "bays": 4,
        "grinding_interval_passages": float("inf"), "stopped": "no", **model_attributes("none", "none")})
    path = tmp_path / "x.nc"
    io.write_netcdf(io.finalize(ds, load_yaml(ROOT / "config/config.yaml"), title="t", source="test"), path)
    with xr.open_dataset(path) as back:
        a = back.attrs
        assert a["wheels"] == 4 and np.issubdtype(type(a["wheels"]), np.integer)
        assert a["speed_m_per_s"] == 40 and np.issubdtype(type(a["speed_m_per_s"]), np.integer)
        assert a["axles_per_train"] == 3.4 and a["eps_m"] == 1e-9 and np.isinf(a["grinding_interval_passages"])
    # at the source: three equal speed classes of a four-axle vehicle, weights 1/3 that sum to 1 only to rounding
    loco = F.Vehicle("loco", (0.0, 2.5, 10.0, 12.5), 1e5, 1350.0, (0.0,) * 4, 0.3)
    coach = F.Vehicle("coach", (0.0, 2.5, 12.0, 14.5), 6e4, 900.0, (0.0,) * 4, 0.7)
    fl = F.Fleet((loco, coach), F.SpeedClasses((36.0, 40.0, 44.0), (1 / 3, 1 / 3, 1 / 3)), 20000.0)
    assert fl.axles_per_train == 4.0
    from rail import chain
    from rail.setup import build

    classes = fl.classes(build.scenario(load_yaml(ROOT / "config/config.yaml")))  # weights 0.3 / 3 and 0.7 / 3
    assert chain.fleet_wheels(classes) == 4.0  # the growth file's wheels


def test_a_narrow_spectrum_near_pinned_pinned_has_tick_labels_markers_and_names_its_track_and_mechanisms(tmp_path):
    # issue 57, item 8: the rate_spectrum.png of a few lines near pinned-pinned (33-38 mm, between the
    # round ticks 30 and 50) had no wavelength tick labels and no markers and named neither the track nor
    # the mechanisms
    from rail.growth_spectrum import RateSpectrum
    from rail.setup import build
    from rail.setup.config import load_yaml
    from rail.studies.rate_spectrum import spectrum_dataset_of

    scn = build.spectrum_scenario(load_yaml(ROOT / "config/config.yaml"))
    N = 48
    lines = np.arange(760, 870, 20)  # 37.9 .. 33.5 mm of a 48-bay period
    rate = (np.linspace(-1, 1, lines.size) * 1e-7).astype(complex)
    sp = RateSpectrum(N * 0.6 / lines, lines, np.zeros(lines.size, dtype=int), rate, rate, np.zeros(lines.size), np.zeros(lines.size),
                      np.zeros(lines.size), 1e-4, 1e-9, N, 1)
    ds = spectrum_dataset_of({39.0: sp}, dataclasses.replace(scn, roughness=dataclasses.replace(scn.roughness, bays=N)))
    assert (ds.attrs["pad_stiffness_N_per_m"], ds.attrs["wear_path"], ds.attrs["normal_contact"]) == (3.5e8, "wheel", "report")
    fig = study_plots.rate_spectrum_figure(ds)
    fig.canvas.draw()
    ax = fig.axes[0]
    labels = [t.get_text() for t in ax.get_xticklabels() if t.get_text()]
    assert len(labels) >= 2 and all(33.0 <= float(x) <= 38.5 for x in labels), labels
    line = next(ln for ln in ax.get_lines() if np.size(ln.get_xdata()) == lines.size)
    assert line.get_marker() == "o"
    assert "track: pad 3.5×10⁸ N/m, sleeper spacing 0.6 m" in ax.get_title()
    notes = " ".join(" ".join(_texts(fig)).split())  # the note is wrapped over lines
    for said in ("normal contact report", "wear path wheel", "wheelset fixed_creepage", "rail flexibility none", "friction step"):
        assert said in notes, said
    fig.savefig(tmp_path / "rate_spectrum.png", dpi=150)
