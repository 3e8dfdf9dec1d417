"""The workflow runs a scenario with a fleet (issue 35, docs/traffic.md): one receptance table per
class speed, named by its content and shared by the fleet's vehicles, a fleet growth run and a fleet spectrum,
study_<name> building them, and the default target untouched. Dry runs only."""

import re

import numpy as np
import pytest

from fleets import TWO_VEHICLES
from test_workflow import assert_stops_at_start_up, job_counts, snakemake, workdir  # noqa: F401 (fixture)

# Runs snakemake in a subprocess with a time limit: .ci/run runs these tests one at a time.
pytestmark = pytest.mark.workflow

MIX = TWO_VEHICLES
# another fleet on the same track: a three-axle vehicle at two of the speeds above and one more
OTHER = """fleet:
  vehicles:
    - name: tram
      positions: [0.0, 1.8, 5.0]
      static_load: 4.0e+4
      unsprung_mass: 500.0
      creepage: [1.0e-4, -0.001, 1.0e-4]
      share: 1.0
  speeds: {values: [40.0, 44.0], weights: [0.5, 0.5]}
"""


def _fleets(workdir, **files):
    """Only the given scenario files (the traffic study's and the ensemble's files removed too: their
    fleets share the default track's tables)."""
    for f in [*(workdir / "config/scenarios").glob("*.yaml"), workdir / "config/traffic_study.yaml", workdir / "config/uncertainty.yaml"]:
        f.unlink()
    for name, text in files.items():
        (workdir / f"config/scenarios/{name}.yaml").write_text(text)


@pytest.mark.slow
def test_a_fleet_study_computes_one_table_per_speed_shared_by_its_vehicles_and_named_by_its_content(root, workdir):
    # issue 36: a fleet's tables are named by the track, numerics and its vehicles' offsets. Before,
    # one table per (track, speed) held every fleet's offsets, so adding a fleet scenario of other
    # vehicles renamed nothing but changed (and reran) every other fleet's tables.
    _fleets(workdir, mix=MIX)
    alone = snakemake(root, "-n", "study_mix", cwd=workdir)
    assert alone.returncode == 0, alone.stderr
    (workdir / "config/scenarios/other.yaml").write_text(OTHER)
    out = snakemake(root, "-n", "study_mix", "study_other", cwd=workdir)
    assert out.returncode == 0, out.stderr
    # mix: 3 speeds (classes at 37.33, 40, 42.67), other: 2 (40, 44): one table each per period (the
    # growth's one bay, the spectrum's N = 48), never one per vehicle
    assert job_counts(out.stdout) == {"fleet_receptance": 5, "fleet_receptance_bloch": 5, "fleet_growth": 2,
                                      "fleet_class_spectrum": 8, "fleet_rate_spectrum": 2, "compile_kernels": 2,
                                      "fleet_bands": 2, "fleet_overview": 2,  # issue 45: a fleet's band view and overview
                                      "fleet_noise": 2,  # issue 56: a fleet's rolling noise
                                      "study_mix": 1, "study_other": 1}  # classes: 2 vehicles x 3 speeds, 1 x 2
    for v in ["37.333333333333336", "40", "42.666666666666664"]:  # the union of the fleet's vehicles' axle offsets
        assert re.search(rf"fleet receptance table: track [0-9a-f]{{10}}, V = {v} m/s, offsets 0\.0 -2\.6 2\.6 -3\.3 3\.3 m", out.stdout), v
    for v in ["40", "44"]:
        assert re.search(rf"fleet receptance table: track [0-9a-f]{{10}}, V = {v} m/s, offsets 0\.0 "
                         rf"-1\.8 1\.8 -3\.2 3\.2 -5\.0 5\.0 m", out.stdout), v
    # adding the other fleet left mix's tables as they were (same files, same offsets)
    tables = re.compile(r"results/receptance/[0-9a-f]{10}/fleet_V[0-9.]+(?:_N[0-9]+)?\.nc")
    assert set(tables.findall(alone.stdout)) and set(tables.findall(alone.stdout)) <= set(tables.findall(out.stdout))
    assert "results/fleet/mix/growth.nc" in out.stdout and "results/fleet/other/rate_spectrum.png" in out.stdout
    assert "rule growth:" not in out.stdout and "rule receptance:" not in out.stdout  # no one-train job


@pytest.mark.slow
def test_a_fleet_scenario_leaves_the_default_target_unchanged(root, workdir, tmp_path):
    out = snakemake(root, "-n", cwd=workdir)
    (workdir / "config/scenarios/mix.yaml").write_text(MIX)
    with_fleet = snakemake(root, "-n", cwd=workdir)
    assert out.returncode == 0 and with_fleet.returncode == 0, with_fleet.stderr
    assert job_counts(with_fleet.stdout) == job_counts(out.stdout)
    assert "results/fleet/" not in with_fleet.stdout and "fleet_V" not in with_fleet.stdout


@pytest.mark.slow
def test_the_traffic_study_computes_each_class_spectrum_once_however_many_cases_hold_it(root, workdir):
    # 8 cases (2 drives x spreads 0, 5, 10, 20 %) hold 2 + 3 x 6 = 20 classes each drive, 40 in all; the
    # distinct ones are the locomotive driven and braked and the coach (the same in both drives), each at
    # the 7 distinct speeds (40 and 40 (1 -+ 2 s / 3)): 21 jobs, 7 tables
    out = snakemake(root, "-n", "traffic_study", cwd=workdir)
    assert out.returncode == 0, out.stderr
    assert job_counts(out.stdout) == {"fleet_receptance_bloch": 7, "fleet_class_spectrum": 21, "fleet_rate_spectrum": 8,
                                      "traffic_study_summary": 1, "traffic_study": 1, "compile_kernels": 1}


def test_a_one_train_target_of_a_fleet_scenario_is_refused_in_one_line(root, workdir):
    _fleets(workdir, mix=MIX)
    out = snakemake(root, "-n", "results/growth/mix/V40.nc", cwd=workdir)
    assert_stops_at_start_up(out, r"scenario 'mix' has a fleet: its growth per speed would run one train and leave the fleet "
                                  r"out; build results/fleet/mix/growth\.nc", workdir)


def test_a_fleets_noise_is_planned_by_rule_fleet_noise_and_a_class_speed_outside_cnossos_stops_it_at_start_up(root, workdir):
    # issue 56: study_mix holds the fleet's noise; a class at 120 m/s (a valid growth speed, outside
    # CNOSSOS-EU's 7.94 .. 100 m/s) leaves it out of study_fast and stops the target asked for by name
    _fleets(workdir, mix=MIX, fast=MIX.replace("{distribution: uniform, low: 36.0, high: 44.0, classes: 3}",
                                               "{values: [40.0, 120.0], weights: [0.5, 0.5]}"))
    out = snakemake(root, "-n", "results/fleet/mix/growth_noise.csv", "study_fast", cwd=workdir)
    assert out.returncode == 0, out.stderr[-2000:]
    assert job_counts(out.stdout)["fleet_noise"] == 1 and "results/fleet/mix/growth_noise.png" in out.stdout  # mix's, not fast's
    assert job_counts(out.stdout)["fleet_bands"] == 1 and "results/fleet/fast/bands.png" in out.stdout
    out = snakemake(root, "-n", "results/fleet/fast/growth_noise.csv", cwd=workdir)
    assert_stops_at_start_up(out, r"scenario 'fast': its fleet's noise cannot be computed: fleet\.speeds: the class speed of loco = "
                                  r"120\.0 m/s is not allowed: CNOSSOS-EU rolling noise is computed here for 7\.94 \.\. 100 m/s", workdir)


def test_a_fleet_roughness_tied_to_one_speed_is_refused_at_start_up(root, workdir):
    # issue 45 (item 9): the file stops the targets that need it (study_mix), not the others
    _fleets(workdir, mix=MIX + "roughness:\n  kind: harmonic\n  frequency: 1000.0\n")
    out = snakemake(root, "-n", "results/figures/fig06.png", cwd=workdir)
    assert out.returncode == 0 and "railgrowth: note: config/scenarios/mix.yaml is not valid" in out.stderr, out.stderr[-2000:]
    out = snakemake(root, "-n", "study_mix", cwd=workdir)
    assert_stops_at_start_up(out, r"config/scenarios/mix\.yaml: roughness\.frequency = 1000\.0 Hz sets the wavelength at one "
                                  r"speed: under a fleet at several speeds give roughness\.wavelength", workdir)


def test_a_fleet_table_at_a_speed_no_fleet_runs_at_is_refused(root, workdir):
    _fleets(workdir, mix=MIX)
    plan = snakemake(root, "-n", "study_mix", cwd=workdir)
    key = re.search(r"results/receptance/([0-9a-f]{10})/fleet_V40\.nc", plan.stdout).group(1)
    out = snakemake(root, "-n", f"results/receptance/{key}/fleet_V41.nc", cwd=workdir)
    assert_stops_at_start_up(out, rf"fleet table '{key}' \(fleets mix\) at V41, which is no class speed of those fleets: "
                                  r"the speeds are 37\.333333333333336, 40, 42\.666666666666664 m/s", workdir)
    # a scenario's name in the key's place is refused with the content-named path
    out = snakemake(root, "-n", "results/receptance/mix/fleet_V40.nc", cwd=workdir)
    assert_stops_at_start_up(out, rf"fleet receptance tables are named by their content, not by a scenario: those of fleet "
                                  rf"'mix' are results/receptance/{key}/fleet_V37\.333333333333336\.nc", workdir)


# ---------------------------------------------------------------- the traffic study (config/traffic_study.yaml)


def _study(root):
    import yaml

    return yaml.safe_load((root / "config/traffic_study.yaml").read_text())


def test_traffic_study_cases_are_fleets_at_the_stated_spreads_about_the_mean_speed(root):
    from rail.fleet import speed_classes
    from rail.setup.study_files import traffic_cases

    study = _study(root)
    cases = traffic_cases(study)
    assert list(cases) == [f"traffic_study-{d}-s{p}" for d in ("driven", "braked") for p in ("0", "5", "10", "20")]
    for name, scen in cases.items():
        s = float(name.rsplit("-s", 1)[1]) / 100
        sc = speed_classes(scen["fleet"]["speeds"])
        v = np.array(sc.speeds)
        assert sc.mean == pytest.approx(40.0, rel=1e-12)
        # uniform on 40 (1 -+ s) in n equal classes: the end classes' centres lie 40 s (1 - 1/n) from the mean
        n = study["classes"] if s else 1
        assert len(v) == n and v.max() - 40.0 == pytest.approx(40.0 * s * (1 - 1 / n), abs=1e-12)
        drive = name.split("-")[1]
        loco = scen["fleet"]["vehicles"][0]
        assert np.sign(loco["creepage"]).tolist() == [-1.0 if drive == "driven" else 1.0] * 4


@pytest.mark.parametrize("key, value, message", [
    ("spreads", [0.0, 0.6], r"spreads\[1\] = 0\.6 is not allowed: it must be a number in \[0, 0\.5\)"),
    ("distribution", "lognormal", r"distribution = 'lognormal' is not allowed: it must be 'uniform' or 'normal'"),
    ("drives", {"driven": {"class87": -0.001}}, r"drives\.driven = .* is not allowed: give one creepage for each vehicle"),
])
def test_a_bad_traffic_study_is_refused_naming_key_and_range(root, key, value, message):
    from rail.setup.study_files import traffic_cases

    study = _study(root)
    study[key] = value
    with pytest.raises(ValueError, match=message):
        traffic_cases(study)


def test_band_rates_average_the_lines_of_each_band_and_leave_an_empty_band_empty():
    from rail.studies.bands import third_octave_bands
    from rail.studies.fleet import band_rates

    bands = third_octave_bands(0.1, 0.08)  # 100 and 80 mm bands
    lam = np.array([0.105, 0.095, 0.090])  # all in the 100 mm band (89.1-112.2 mm)
    out = band_rates(lam, np.array([1.0, 2.0, 6.0]), bands)
    assert out[0] == 3.0 and np.isnan(out[1])


@pytest.mark.slow
def test_the_uncertainty_ensemble_runs_one_spectrum_per_member_and_a_bad_draw_stops_at_start_up(root, workdir):
    out = snakemake(root, "-n", "uncertainty", cwd=workdir)
    assert out.returncode == 0, out.stderr
    assert job_counts(out.stdout) == {"uncertainty_member": 16, "uncertainty_ensemble": 1, "uncertainty": 1, "compile_kernels": 1}
    f = workdir / "config/uncertainty.yaml"
    f.write_text(f.read_text().replace("{distribution: uniform, low: 0.2, high: 0.4}", "{distribution: uniform, low: 0.4, high: 0.2}"))
    bad = snakemake(root, "-n", "uncertainty", cwd=workdir)
    assert_stops_at_start_up(bad, r"config/uncertainty\.yaml: uncertainty parameter contact\.friction: low = 0\.4, high = 0\.2 "
                                  r"are not allowed: low <= high", workdir)


@pytest.mark.slow
def test_a_fleet_whose_wheels_are_a_source_plans_its_settled_spectrum_and_renames_only_the_rough_vehicles_classes(root, workdir):
    # issue 58 for fleets: the locomotive's wheels disc-braked (its own wheel_source), the coaches' cast iron (the
    # top-level roughness they take): study_mix plans fleet_settled_spectrum from the fleet's spectrum; without the
    # source the class files are those of before (the same names), with it every class of a rough vehicle another
    _fleets(workdir, mix=MIX)
    plain = snakemake(root, "-n", "study_mix", cwd=workdir)
    rough = MIX.replace("share: 0.4", "share: 0.4\n      wheel_source: {roughness: disc}", 1) + "wheel_source: {roughness: cast_iron}\n"
    (workdir / "config/scenarios/mix.yaml").write_text(rough)
    out = snakemake(root, "-n", "study_mix", cwd=workdir)
    assert plain.returncode == 0 and out.returncode == 0, out.stderr
    counts = job_counts(out.stdout)
    assert counts.pop("fleet_settled_spectrum") == 1 and counts == job_counts(plain.stdout)
    for x in ("png", "csv", "md"):
        assert f"results/fleet/mix/settled.{x}" in out.stdout
    keys = re.compile(r"results/fleet/classes/([A-Za-z0-9.-]+_V[0-9.e+-]+_[0-9a-f]{16})\.npz")
    before, after = set(keys.findall(plain.stdout)), set(keys.findall(out.stdout))
    assert len(before) == len(after) == 6 and before.isdisjoint(after)  # both vehicles' wheels are rough here
    (workdir / "config/scenarios/mix.yaml").write_text(MIX.replace("share: 0.6", "share: 0.6\n      wheel_source: {roughness: none}", 1)
                                                     .replace("share: 0.4", "share: 0.4\n      wheel_source: {roughness: disc}", 1))
    half = snakemake(root, "-n", "study_mix", cwd=workdir)
    assert half.returncode == 0, half.stderr
    mixed = set(keys.findall(half.stdout))
    assert len(mixed & before) == 3 and all(k.startswith("coach_") for k in mixed & before)  # the smooth coaches keep theirs
