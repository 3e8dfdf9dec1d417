"""The dynamic-creepage study over speed (rail.studies.speed_study): what each case holds, read from its
configuration; the verdict on frequency against wavelength; the dataset's lines and its pinned-pinned line."""

import os
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml

from rail.setup.config import load_yaml, validate_config
from rail.setup.plan import plan
from rail.studies import speed_study

ROOT = Path(__file__).resolve().parents[1]
LAM = 2 * 0.6 / np.arange(10, 61)  # the lines of 2 bays: 120 mm to 20 mm


@pytest.fixture(scope="module")
def scenarios():
    here = Path.cwd()
    os.chdir(ROOT)
    try:
        schema = load_yaml("config/schema/config.schema.yaml")
        yield plan(validate_config(load_yaml("config/config.yaml"), schema), schema).scenarios
    finally:
        os.chdir(here)


def test_each_study_file_is_labelled_by_what_its_configuration_switches_on(scenarios):
    want = {"fixed": "fixed creepage", "trailer": "trailer wheelset", "driven": "motored wheelset", "rail": "rail flexibility",
            "falling": "falling friction", "together": "motored wheelset + rail flexibility + falling friction"}
    for m, label in want.items():
        for t in ("", "_stiff"):
            assert speed_study.mechanism_label(scenarios[f"dynspeed_{m}{t}"]) == label
            assert speed_study.track_label(scenarios[f"dynspeed_{m}{t}"]) == speed_study.track_label(scenarios[f"dynspeed_fixed{t}"])
    assert speed_study.track_label(scenarios["dynspeed_fixed_stiff"]) == "pad 1e+09 N/m"
    assert speed_study.track_label(scenarios["dynspeed_fixed"]) != speed_study.track_label(scenarios["dynspeed_fixed_stiff"])
    # a friction law that does not fall (mu_d = mu_s) is no falling friction
    assert speed_study.mechanism_label({"contact": {"friction_static": 0.3, "friction_dynamic": 0.3, "friction_decay": 1.0}}) == "fixed creepage"


def _spectra(rate_of, speeds=(20.0, 40.0, 60.0, 80.0), cfg=None):
    cfg = cfg or {"track": {"pad": {"stiffness": 1.3e9}}}
    out = []
    for V in speeds:
        r = rate_of(V, V / LAM)
        out.append(xr.Dataset({"growth_dB_per_1e5_axles": (("speed", "wavelength"), r[None, :])},
                              coords={"speed": [V], "wavelength": LAM}, attrs={"config": yaml.safe_dump(cfg)}))
    return out


def _bump(centre_f=None, centre_lam=None, peak=0.3):
    def rate(V, f):
        x = np.log(f / centre_f) if centre_f else np.log((V / f) / centre_lam)
        return peak - 2.0 * x ** 2 * 10
    return rate


def test_a_band_at_one_frequency_is_said_to_keep_its_frequency_and_one_at_one_wavelength_its_wavelength():
    cases = {"f": _spectra(_bump(centre_f=1000.0)), "lam": _spectra(_bump(centre_lam=0.05)),
             "none": _spectra(lambda V, f: -1.0 - 0 * f)}
    ds = speed_study.study_dataset(cases, {n: 1069.0 for n in cases})
    assert ds["verdict"].sel(case="f").item().startswith("constant frequency")
    assert ds["verdict"].sel(case="lam").item().startswith("constant wavelength")
    assert ds["verdict"].sel(case="none").item() == "nothing grows"
    # the fastest line of the frequency case is the line nearest 1 kHz at each speed, and it grows
    f = ds["fastest_frequency"].sel(case="f").values
    assert np.all(np.abs(np.log(f / 1000.0)) <= np.log(LAM[:-1] / LAM[1:]).max())
    assert np.all(ds["fastest_dB_per_1e5_axles"].sel(case="f").values > 0)
    np.testing.assert_allclose(ds["fastest_wavelength"].sel(case="lam").values, LAM[np.argmin(np.abs(LAM - 0.05))])


def test_a_peak_on_the_range_edge_is_said_to_be_there_and_one_speed_is_not_a_trend():
    edge = {"e": _spectra(lambda V, f: np.where(V / f >= LAM.max() * 0.999, 0.1, -1.0) + 0 * f)}
    v = speed_study.study_dataset(edge, {"e": 1069.0})["verdict"].item()
    assert v.startswith("constant wavelength") and "edge" in v
    one = {"o": _spectra(lambda V, f: np.where((V == 40.0) & (np.abs(f - 1000) < 30), 0.2, -1.0) + 0 * f)}
    assert speed_study.study_dataset(one, {"o": 1069.0})["verdict"].item().startswith("grows at one speed only (40 m/s")


def test_the_pinned_pinned_line_is_the_line_nearest_its_frequency_and_mismatched_lines_are_refused():
    cases = {"a": _spectra(lambda V, f: -np.abs(np.log(f / 1069.0)))}
    ds = speed_study.study_dataset(cases, {"a": 1069.0})
    for V in ds["speed"].values:
        want = LAM[np.argmin(np.abs(np.log(V / LAM / 1069.0)))]
        assert ds["pinned_pinned_wavelength"].sel(case="a", speed=V).item() == want
    bad = _spectra(lambda V, f: 0 * f)
    bad[1] = bad[1].assign_coords(wavelength=LAM * 1.01)
    with pytest.raises(ValueError, match="lines"):
        speed_study.study_dataset({"a": cases["a"], "b": bad}, {"a": 1069.0, "b": 1069.0})
    table = speed_study.summary_table(ds)
    assert table.count("\n| fixed creepage |") == 4 + 1  # four speeds and the verdict


def test_the_figures_frequency_tick_labels_are_plain_and_do_not_overlap():
    # a panel per mechanism and track, as the study's twelve files give: log frequency axes ticked at round
    # values written plainly (200, 500, 1000, not 2×10²) whose labels do not run into each other
    from rail.plotting.speed_study import speed_study_figure
    cases = {n: _spectra(_bump(centre_f=1000.0)) for n in ("a", "b", "c", "d", "e", "f")}
    fig = speed_study_figure(speed_study.study_dataset(cases, {n: 1069.0 for n in cases}))
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    for ax in fig.axes:
        labels = [t for t in ax.get_xticklabels(which="both") if t.get_visible() and t.get_text()]
        if not labels:
            continue
        assert all("times" not in t.get_text() and "^" not in t.get_text() for t in labels), [t.get_text() for t in labels]
        boxes = sorted((t.get_window_extent(r) for t in labels), key=lambda b: b.x0)
        assert all(a.x1 < b.x0 for a, b in zip(boxes, boxes[1:])), [t.get_text() for t in labels]


def test_a_fastest_line_that_moves_to_another_band_is_said_to_be_two_bands():
    """Two bands, each at its own frequency: one at 250 Hz that grows at low speed and fades, one at
    1,100 Hz that grows at high speed. The fastest line's wavelength shortens as the speed rises, which
    one band cannot do: the verdict says two bands and where the change is, not a constant wavelength.
    Either band alone keeps its frequency."""
    def two(V, f):
        low = 0.4 - 40.0 * np.log(f / 250.0) ** 2 - 0.02 * (V - 20.0)
        high = -0.8 + 0.02 * V - 40.0 * np.log(f / 1100.0) ** 2
        return np.maximum(low, high)
    ds = speed_study.study_dataset({"t": _spectra(two)}, {"t": 1069.0})
    v = ds["verdict"].item()
    lam = ds["fastest_wavelength"].sel(case="t").values
    assert np.any(np.diff(lam) < 0)  # the fastest line's wavelength shortens somewhere as the speed rises
    assert v.startswith("two bands: the fastest line changes band between"), v
    assert "constant wavelength" not in v
    for fc, speeds in ((250.0, (20.0, 25.0, 30.0)), (1100.0, (60.0, 70.0, 80.0))):  # where each band is in the lines
        band = _spectra(lambda V, f: 0.4 - 40.0 * np.log(f / fc) ** 2 + 0 * V, speeds=speeds)
        assert speed_study.study_dataset({"b": band}, {"b": 1069.0})["verdict"].item().startswith("constant frequency")
