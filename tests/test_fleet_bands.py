"""A fleet run carries the outputs a one-train run has (issue 45): bands, growth per band, the grinding
interval with its band in passages, years and MGT of the fleet's traffic, the band, narrow-band and
rolling-noise exports, through every door alike: the API (api.bands), the command line (`railgrowth
run` without --speed, `railgrowth bands`) and the workflow (rules fleet_bands, fleet_overview), all
through rail.studies.exports.band_outputs."""

import csv
import importlib.util
import io

import numpy as np
import pytest
import xarray as xr

from rail.app import api, cli

# Runs snakemake or sphinx in a subprocess with a time limit: .ci/run runs these tests one at a time.
pytestmark = pytest.mark.workflow

# two one-wheel vehicles at one speed, from the example spectrum over one bay, reduced numerics
# (K = 36 is the least the configured speeds allow; 21 contact nodes)
TINY = """fleet:
  vehicles:
    - name: loco
      positions: [0.0]
      static_load: 1.0e+5
      unsprung_mass: 1350.0
      creepage: [-0.001]
      share: 0.4
    - name: coach
      positions: [0.0]
      static_load: 6.0e+4
      unsprung_mass: 900.0
      creepage: [0.0005]
      share: 0.6
  speeds: {values: [40.0], weights: [1.0]}
roughness:
  kind: spectrum
  file: config/roughness/example_spectrum.csv
  bays: 1
  seed: 1
numerics:
  track: {harmonics: 36}
  contact: {nodes: 21}
growth: {passages: 20000, passages_per_update: 10000, save_every: 10000}
"""


def _rows(text):
    return list(csv.DictReader(io.StringIO("\n".join(x for x in text.splitlines() if not x.startswith("#")))))


def _script(root, name):
    """A workflow script as a module (its snakemake block runs only as __main__)."""
    spec = importlib.util.spec_from_file_location(name, root / f"workflow/scripts/{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _fleet_like_growth(K=36):
    """A growth dataset as a fleet run writes it (levels per line at every save, one bay): the example
    spectrum's 50 mm band growing at +0.3 dB per 100,000 axles, the 200 mm band from nothing at -60 dB."""
    n = np.arange(0, 20001, 10000, dtype=float)
    J = K
    Z = np.zeros((len(n), 2 * J + 1), dtype=complex)
    for j, a in {12: 1e-6 * 10 ** (7 / 20) * np.sqrt(2) * np.exp(0.3 / 8.685889638 * n / 1e5),
                 3: np.sqrt(2) * (1e-9 + 3e-9 * n / 1e5)}.items():
        Z[:, J + j] = Z[:, J - j] = a / 2
    lev = 20 * np.log10(np.maximum(np.abs(Z[:, J + 1:]) * np.sqrt(2), 1e-30) / 1e-6)
    return xr.Dataset({"Z_real": (("passage", "h"), Z.real), "Z_imag": (("passage", "h"), Z.imag),
                       "level": (("passage", "harmonic"), lev),
                       "exponential_rate": ("harmonic", np.zeros(J)), "amplitude_growth_rate": ("harmonic", np.zeros(J))},
                      coords={"passage": n, "harmonic": np.arange(1, J + 1)},
                      attrs={"bays": 1, "speed_m_per_s": 40.0, "fleet_speeds": "[40.0] m/s with weights [1.0] (values)",
                             "fleet_vehicles": "loco: share 0.4, ...; coach: share 0.6, ..."})


def _grown_by(growth, study):
    """The growth dataset with the provenance a growth run writes (rail.setup.io.finalize): the
    scenario's name and its resolved configuration, which the band view checks (issue 57)."""
    import yaml

    growth.attrs.update(scenario=study.name, config=yaml.safe_dump(study.config, sort_keys=True))
    return growth


def test_a_fleet_growth_file_is_refused_by_another_scenarios_band_view_naming_the_fleet(tmp_path, capsys):
    # issue 57, item 3: `railgrowth bands default <a fleet's growth file>` exited 0 with the default
    # train's axle load (27.9 MGT a year) instead of the fleet's, and relabelled the file as default's
    scen = tmp_path / "tiny_fleet.yaml"
    scen.write_text(TINY)
    gpath = tmp_path / "growth.nc"
    _grown_by(_fleet_like_growth(), api.load(scen)).to_netcdf(gpath)
    out = tmp_path / "default_view.nc"
    assert cli.main(["bands", "default", str(gpath), "--out", str(out)]) == cli.EXIT_INPUT
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and err.startswith(f"railgrowth: {gpath}: was computed for another scenario or configuration than default"), err
    assert "scenario: 'tiny_fleet' / 'default'" in err and "fleet: given / not given" in err, err
    assert "Give the scenario it was grown from (its attribute scenario: 'tiny_fleet')" in err
    assert list(tmp_path.glob("default_view*")) == []
    from rail.setup.config import ConfigError

    with pytest.raises(ConfigError, match=r"fleet: given / not given"):
        api.bands(api.load("default"), xr.open_dataset(gpath).load())


def test_a_fleet_growth_is_banded_alike_by_the_api_the_command_line_and_the_workflow_script(root, tmp_path, capsys):
    # fast: one growth dataset, the three doors; they must give the same files, and the fleet's
    # traffic (not a one-train traffic) sets the years and MGT
    scen = tmp_path / "tiny_fleet.yaml"
    scen.write_text(TINY)
    study = api.load(scen)
    growth = _grown_by(_fleet_like_growth(), study)
    gpath = tmp_path / "growth.nc"
    growth.to_netcdf(gpath)

    b = api.bands(study, growth)
    assert cli.main(["bands", str(scen), str(gpath), "--out", str(tmp_path / "cli_bands.nc")]) == 0
    assert "grinding interval: limit exceeded after" in capsys.readouterr().out
    wf = {k: tmp_path / f"wf_{k}" for k in ("data", "csv", "narrow_csv", "rolling_noise_csv", "figure")}
    wf["figure"] = tmp_path / "wf.png"
    _script(root, "growth_bands").main(study.config, study.name, str(gpath), wf)

    assert (tmp_path / "cli_bands.csv").read_text() == wf["csv"].read_text() == b.bands_csv
    assert (tmp_path / "cli_rolling_noise_roughness.csv").read_text() == wf["rolling_noise_csv"].read_text() == b.rolling_noise_csv
    assert (tmp_path / "cli_narrowband.csv").read_text() == wf["narrow_csv"].read_text() == b.narrow_csv
    with xr.open_dataset(tmp_path / "cli_bands.nc") as c, xr.open_dataset(wf["data"]) as w:
        np.testing.assert_array_equal(c["level"].values, b.data["level"].values)
        np.testing.assert_array_equal(w["level"].values, b.data["level"].values)
        assert c.attrs["grinding_interval_passages"] == w.attrs["grinding_interval_passages"] == b.data.attrs["grinding_interval_passages"]

    # the fleet's traffic: 20,000 axles a day of 0.4 x 100 kN and 0.6 x 60 kN wheels (one axle each)
    a = b.data.attrs
    axle_t = 2 * (0.4 * 1e5 + 0.6 * 6e4) / 9.80665 / 1000
    assert a["axle_load_t"] == pytest.approx(axle_t, rel=1e-12)
    assert a["mgt_per_year"] == pytest.approx(20000 * 365 * axle_t / 1e6, rel=1e-12)
    # the 50 mm band from 7 dB at +0.3 dB per 1e5 axles exceeds the example limit 8.5 (to 0.05: 8.55 dB)
    assert a["grinding_interval_band_m"] == 0.05
    assert a["grinding_interval_passages"] == pytest.approx(1e5 * 1.55 / 0.3, rel=1e-6)
    assert a["grinding_interval_years"] == pytest.approx(a["grinding_interval_passages"] / 20000 / 365, rel=1e-12)
    assert a["grinding_interval_MGT"] == pytest.approx(a["grinding_interval_years"] * a["mgt_per_year"], rel=1e-12)
    # the 200 mm band grown from nothing is not ranked; the rolling-noise export fills the bands the
    # one-bay period cannot hold (longer than 0.6 m) from the input spectrum and says so
    rows = {float(r["nominal_wavelength_m"]): r for r in _rows(b.bands_csv)}
    assert rows[0.2]["ranked"] == "0" and "below the floor" in rows[0.2]["rate_note"]
    noise = {float(r["wavelength_mm"]): r for r in _rows(b.rolling_noise_csv)}
    assert noise[800.0]["source"] == "input spectrum" and float(noise[800.0]["rail_roughness_dB_re_1um"]) == 13.0
    assert noise[50.0]["source"] == "model" and noise[200.0]["rail_roughness_dB_re_1um"] == ""
    assert "filled from the input spectrum" in b.rolling_noise_csv
    # a fleet's files say so: the speed is the fleet's mean, the passages the fleet's traffic's
    assert "# fleet at mean speed 40 m/s" in b.bands_csv and "# fleet: loco: share 0.4" in b.bands_csv
    assert "under its fleet (frequency at its mean speed)" in b.rolling_noise_csv
    assert b.data.attrs["fleet_speeds"].startswith("[40.0] m/s")


def test_run_without_speed_is_only_for_a_fleet(tmp_path, capsys, monkeypatch):
    def never(*args, **kwargs):
        raise AssertionError("computed before the arguments were checked")

    monkeypatch.setattr(api.chain, "receptance_table", never)
    assert cli.main(["run", "default"]) == 2
    assert "--speed is needed for default: a train speed in m/s (only a scenario with a fleet runs without it)." in capsys.readouterr().err


@pytest.mark.slow
def test_a_fleet_study_gives_the_same_bands_in_the_workflow_the_command_line_and_the_api(root, tmp_path, capsys):
    # about 90 s on 2 cores (measured): the fleet grown three times (20,000 axle passages, K = 36, 21 nodes)
    import os
    import shutil

    from test_workflow import snakemake

    work = tmp_path / "work"
    shutil.copytree(root / "config", work / "config")
    for f in [*(work / "config/scenarios").glob("*.yaml"), work / "config/traffic_study.yaml", work / "config/uncertainty.yaml"]:
        f.unlink()
    (work / "config/scenarios/tiny_fleet.yaml").write_text(TINY)
    out = snakemake(root, "-j2", "results/fleet/tiny_fleet/bands.csv", "results/fleet/tiny_fleet/overview.png", cwd=work)
    assert out.returncode == 0, out.stderr[-3000:]
    workflow_rows = _rows((work / "results/fleet/tiny_fleet/bands.csv").read_text())

    here = os.getcwd()
    os.chdir(work)
    try:
        assert cli.main(["--root", str(work), "run", "tiny_fleet", "--bands", "--out", str(tmp_path / "cli.nc")]) == 0
        study = api.load("tiny_fleet", root=work)
        b = api.bands(study, api.growth(study, progress=io.StringIO()))
    finally:
        os.chdir(here)
    assert "grinding interval:" in capsys.readouterr().out
    cli_rows = _rows((tmp_path / "cli_bands.csv").read_text())
    api_rows = _rows(b.bands_csv)
    level_cols = [c for c in workflow_rows[0] if c.startswith("level_dB")]
    assert len(level_cols) == 3
    for w, c, a in zip(workflow_rows, cli_rows, api_rows, strict=True):
        assert w["nominal_wavelength_m"] == c["nominal_wavelength_m"] == a["nominal_wavelength_m"]
        assert w["ranked"] == c["ranked"] == a["ranked"]
        for col in level_cols + ["growth_dB_per_1e5_axles", "growth_dB_per_year"]:
            # the CSV's rounding (.3f, .4g); the workflow reads its tables from files (2.5e-13, docs/traffic.md)
            assert w[col] == c[col] == a[col], (w["nominal_wavelength_m"], col)
    with xr.open_dataset(work / "results/fleet/tiny_fleet/bands.nc") as w, xr.open_dataset(tmp_path / "cli_bands.nc") as c:
        for key in ("grinding_interval_passages", "grinding_interval_years", "grinding_interval_MGT", "grinding_interval_band_m"):
            for other in (c.attrs[key], b.data.attrs[key]):
                assert other == pytest.approx(w.attrs[key], rel=1e-9, nan_ok=True), key
        np.testing.assert_allclose(c["level"].values, w["level"].values, rtol=0, atol=1e-9)
        np.testing.assert_allclose(b.data["level"].values, w["level"].values, rtol=0, atol=1e-9)
    assert (work / "results/fleet/tiny_fleet/overview.png").stat().st_size > 10000
    assert (work / "results/fleet/tiny_fleet/rolling_noise_roughness.csv").exists()
    # the HTML report holds the fleet's band view beside its other outputs
    rep = snakemake(root, "--report", "report.html", "report_all", cwd=work)
    assert rep.returncode == 0, rep.stderr[-3000:]
    html = (work / "report.html").read_text(errors="replace")
    assert "Traffic (fleet)" in html and "rolling_noise_roughness.csv" in html and "overview.png" in html
