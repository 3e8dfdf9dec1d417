"""The workflow: targets compute only what they need, bad input stops it before any job,
and a real run writes self-describing data and a picture."""

import re
import shutil
import subprocess
import sys

import pytest
import xarray as xr
import yaml

# Runs snakemake or sphinx in a subprocess with a time limit: .ci/run runs these tests one at a time.
pytestmark = pytest.mark.workflow


def snakemake(root, *args, cwd=None):
    cmd = [sys.executable, "-m", "snakemake", "-s", str(root / "Snakefile"), *args]
    return subprocess.run(cmd, cwd=cwd or root, capture_output=True, text=True, timeout=300)


def job_outputs(output: str) -> dict[str, list[str]]:
    """Parse a dry run's job blocks into {rule: [output files of each job, comma-joined]}."""
    jobs = {}
    for m in re.finditer(r"^(?:local)?rule (\w+):\n(.*?)(?:\n\n|\Z)", output, re.M | re.S):
        out = re.search(r"^\s+output: (.*)$", m.group(2), re.M)
        jobs.setdefault(m.group(1), []).append(out.group(1) if out else "")
    return jobs


def table_paths(output: str) -> list[str]:
    """The receptance tables a dry run plans to build (content-named: results/receptance/<key>/V...nc), from
    the jobs' messages."""
    return sorted(set(re.findall(r"receptance tables? (results/receptance/[0-9a-f]{10}/V[^\s,:]+\.nc)", output)))


def job_counts(output: str) -> dict[str, int]:
    """Parse the 'Job stats' table of a dry run into {rule: count}."""
    table = output.split("Job stats:")[1].split("total")[0]
    return {m.group(1): int(m.group(2)) for m in re.finditer(r"^(\w+)\s+(\d+)\s*$", table, re.M)}


def assert_stops_at_start_up(out, pattern, workdir=None):
    """The run failed, with a message matching ``pattern``, and (given its folder) built nothing."""
    assert out.returncode != 0
    assert re.search(pattern, out.stderr + out.stdout), (out.stderr + out.stdout)[-2000:]
    if workdir is not None:
        assert not (workdir / "results").exists()


@pytest.fixture()
def workdir(root, tmp_path):
    """An empty working directory holding only the configuration."""
    shutil.copytree(root / "config", tmp_path / "config")
    return tmp_path


@pytest.mark.slow
def test_fig06_alone_runs_only_the_radiation_jobs(root, workdir):
    out = snakemake(root, "-n", "results/figures/fig06.png", cwd=workdir)
    assert out.returncode == 0, out.stderr
    assert job_counts(out.stdout) == {"halfspace_radiation": 1, "radiation_figures": 1}


def test_default_target_builds_every_figure_and_only_the_receptances_they_need(root, workdir):
    out = snakemake(root, "-n", cwd=workdir)
    assert out.returncode == 0, out.stderr
    assert job_counts(out.stdout) == {
        "halfspace_figures": 1,  # Figs 2-4 in one job (issue 33: a job's start-up costs more than a figure)
        "halfspace_radiation": 1,
        "radiation_figures": 1,  # Figs 5-6
        # content-named tables (issue 36): the default track with one wheel at 20, 40, 60, 80 m/s; soft_pad's
        # track at 40 m/s only; class87's four wheels (its own offsets) at 20 and 40 m/s
        "receptance": 7,
        "fig08": 1,
        "fig22": 1,
        "wear_cases": 1,  # 533, 1000, 1200, 1600 Hz at 40 m/s, in one job
        "wear_figures": 1,  # Figs 9-19 in one job
        "growth": 7,  # default at 4 speeds, soft_pad at 40, class87 at 20 and 40 m/s
        "growth_figures": 1,  # Figs 20, 21, 23-27 in one job
        "growth_3d": 1,
        "compile_kernels": 1,  # the contact march, compiled once before the wear and growth jobs
        "all": 1,
    }
    # a roughness input the period cannot hold in full is one note naming its scenarios, said once,
    # not a Python warning with a line of rail's source under it
    notes = [line for line in out.stderr.splitlines() if "example_limit_minus10.csv" in line]
    assert len(notes) == 1 and notes[0].startswith("railgrowth: note (scenario short_wave_study, short_wave_study_report): ")
    assert "RoughnessInputWarning" not in out.stderr and "return Roughness(" not in out.stderr


@pytest.mark.parametrize(
    "override, message",
    [
        ({"material": {"poisson_ratio": 0.5}}, r"material\.poisson_ratio = 0\.5 is not allowed: it must be < 0\.5 \(valid range \(-1, 0\.5\)\)"),
        # one start-up refusal in the default run; the others (a Snakemake start-up each, 6-8 s) in the slow run
        pytest.param({"track": {"ballast": {"stiffness": -5.0e7}}},
                     r"track\.ballast\.stiffness = -50000000\.0 N/m is not allowed: it must be > 0 N/m",
                     marks=pytest.mark.slow),
        pytest.param({"wheels": {"mas": 1350.0}}, r"unknown key wheels\.mas = 1350\.0", marks=pytest.mark.slow),
    ],
)
def test_bad_configfile_stops_before_any_job(root, workdir, override, message):
    bad = workdir / "bad.yaml"
    bad.write_text(yaml.safe_dump(override))
    out = snakemake(root, "-j1", "--configfile", str(bad), cwd=workdir)
    assert out.returncode != 0
    assert re.search(message, out.stderr + out.stdout), out.stderr
    assert not (workdir / "results").exists()  # nothing was computed


@pytest.mark.slow
def test_fig06_run_writes_labelled_data_and_picture(root, workdir):
    out = snakemake(root, "-j1", "results/figures/fig06.png", cwd=workdir)
    assert out.returncode == 0, out.stderr
    assert (workdir / "results/figures/fig06.png").stat().st_size > 10_000
    with xr.open_dataset(workdir / "results/data/fig06.nc") as ds:
        for name, var in list(ds.data_vars.items()) + list(ds.coords.items()):
            assert var.attrs["units"] and var.attrs["long_name"], name
        config = yaml.safe_load(ds.attrs["config"])
        assert config["contact"]["hertz_stiffness"] == 1.4e9
        assert "numpy" in yaml.safe_load(ds.attrs["package_versions"])
        # the figure's own physics: eta_H proportional to frequency, zero at 0 Hz
        eta, f = ds["loss_factor"].values, ds["frequency"].values
        assert eta[0] == 0.0
        assert (eta[1:] / f[1:]).std() < 1e-8 * (eta[1:] / f[1:]).mean()


@pytest.mark.slow
def test_bad_scenario_file_is_named_and_stops_before_any_job(root, workdir):
    # the report figures need soft_pad (Figs 24, 25): the default target stops (issue 45: only targets that need it)
    (workdir / "config/scenarios/soft_pad.yaml").write_text("track:\n  pad:\n    stiffness: -7.0e+7\n")
    out = snakemake(root, "-j1", cwd=workdir)
    assert_stops_at_start_up(
        out, r"config/scenarios/soft_pad\.yaml: track\.pad\.stiffness = -70000000\.0 N/m is not allowed: it must be > 0 N/m", workdir)


@pytest.mark.slow
def test_each_receptance_table_holds_the_offsets_of_the_wheels_it_serves(root, workdir):
    # issue 36: a table is named by its content (track, track numerics, wheel offsets), so a two-wheel
    # scenario on the default track gets a table of its own (it no longer adds its spacing to the
    # default table, which reran every default job); a scenario with a different track gets its own
    for f in (workdir / "config/scenarios").glob("*.yaml"):
        f.unlink()
    (workdir / "config/scenarios/bogie.yaml").write_text("wheels:\n  positions: [0.0, 3.3]\n")
    (workdir / "config/scenarios/soft.yaml").write_text("track:\n  pad:\n    stiffness: 7.0e+7\n")
    (workdir / "config/scenarios/same.yaml").write_text("contact:\n  creepage: -0.002\n")  # the default's track and wheel
    runs = [f"results/growth/{s}/V40.nc" for s in ("default", "bogie", "soft", "same")]
    out = snakemake(root, "-n", *runs, cwd=workdir)
    assert out.returncode == 0, out.stderr
    assert job_counts(out.stdout)["receptance"] == 3
    offsets = sorted(re.findall(r"receptance table results/receptance/[0-9a-f]{10}/V40\.nc: V = 40 m/s, offsets (.*) m", out.stdout))
    assert offsets == ["0.0", "0.0", "0.0 -3.3 3.3"]


@pytest.mark.slow
def test_sweep_expands_into_one_growth_run_per_grid_point(root, workdir):
    for f in [*(workdir / "config/scenarios").glob("*.yaml"), *(workdir / "config/studies").glob("*.yaml")]:
        f.unlink()  # the study files hold scenarios and sweeps too
    (workdir / "config/scenarios/grid.yaml").write_text(
        "sweep:\n  speed: [20.0, 40.0]\n  contact.creepage: [-0.001, -0.002, -0.003]\n"
    )
    out = snakemake(root, "-n", "sweeps", cwd=workdir)
    assert out.returncode == 0, out.stderr
    counts = job_counts(out.stdout)
    assert counts["growth"] == 6 and counts["sweep_aggregate"] == 1
    assert counts["receptance"] == 2  # creepage does not change the track: tables shared per speed


@pytest.mark.slow
def test_bad_sweep_value_names_the_file_and_the_point(root, workdir):
    (workdir / "config/scenarios/grid.yaml").write_text("sweep:\n  track.pad.stiffness: [3.5e+8, -1.0e+8]\n")
    out = snakemake(root, "-n", "sweeps", cwd=workdir)
    assert out.returncode != 0
    assert re.search(
        r"config/scenarios/grid\.yaml \(sweep point track\.pad\.stiffness = -100000000\.0\): "
        r"track\.pad\.stiffness = -100000000\.0 N/m is not allowed",
        out.stderr + out.stdout,
    ), out.stderr


@pytest.mark.slow
def test_scenario_and_sweep_files_ending_in_yml_are_part_of_the_workflow(root, workdir):
    # issue 32 (item 6): *.yml was silently skipped (the workflow read *.yaml only)
    for f in [*(workdir / "config/scenarios").glob("*.yaml"), *(workdir / "config/studies").glob("*.yaml")]:
        f.unlink()  # the study files hold scenarios and sweeps too
    (workdir / "config/scenarios/soft.yml").write_text("track:\n  pad:\n    stiffness: 7.0e+7\n")
    (workdir / "config/scenarios/grid.yml").write_text("sweep:\n  speed: [20.0, 40.0]\n")
    out = snakemake(root, "-n", "results/growth/soft/V40.nc", "sweeps", cwd=workdir)
    assert out.returncode == 0, out.stderr
    counts = job_counts(out.stdout)
    assert counts["growth"] == 3 and counts["sweep_aggregate"] == 1
    assert counts["receptance"] == 3  # soft's table at 40 m/s; the sweep's (default track) at 20 and 40 m/s


@pytest.mark.slow
def test_two_scenario_files_of_one_name_stop_before_any_job(root, workdir):
    (workdir / "config/scenarios/soft_pad.yml").write_text("track:\n  pad:\n    stiffness: 7.0e+7\n")
    out = snakemake(root, "-n", cwd=workdir)
    assert_stops_at_start_up(
        out, r"config/scenarios/soft_pad\.yaml and config/scenarios/soft_pad\.yml: both give the scenario name 'soft_pad'; "
             r"keep one of them\.", workdir)


@pytest.mark.slow
def test_slurm_profile_plans_the_default_target(root, workdir):
    import shutil as sh

    sh.copytree(root / "profiles", workdir / "profiles")
    out = snakemake(root, "--profile", "profiles/slurm", "-n", "results/figures/fig06.png", cwd=workdir)
    assert out.returncode == 0, out.stderr
    assert job_counts(out.stdout) == {"halfspace_radiation": 1, "radiation_figures": 1}


@pytest.mark.slow
def test_changing_a_scenario_reruns_only_its_jobs(root, workdir):
    # two scenarios with their own tracks; after both tables are built, editing one scenario
    # makes exactly its table out of date (the tables carry only their track and numerics)
    for f in (workdir / "config/scenarios").glob("*.yaml"):
        f.unlink()
    small = "numerics:\n  track:\n    harmonics: 33\n"  # the least K that reaches pinned-pinned at 20 m/s
    (workdir / "config/scenarios/a.yaml").write_text("track:\n  pad:\n    stiffness: 2.0e+8\n" + small)
    (workdir / "config/scenarios/b.yaml").write_text("track:\n  pad:\n    stiffness: 1.0e+8\n" + small)
    runs = ["results/growth/a/V40.nc", "results/growth/b/V40.nc"]
    plan = snakemake(root, "-n", *runs, cwd=workdir)
    tables = table_paths(plan.stdout)
    assert len(tables) == 2  # a's and b's (their tracks differ)
    built = snakemake(root, "-j1", *tables, cwd=workdir)
    assert built.returncode == 0, built.stderr
    again = snakemake(root, "-n", *runs, cwd=workdir)
    assert "receptance" not in job_counts(again.stdout)
    (workdir / "config/scenarios/b.yaml").write_text("track:\n  pad:\n    stiffness: 0.7e+8\n" + small)
    out = snakemake(root, "-n", *runs, cwd=workdir)
    assert job_counts(out.stdout)["receptance"] == 1 and job_counts(out.stdout)["growth"] == 2
    new = table_paths(out.stdout)  # b's new track has a table of its own name; a's is untouched
    assert len(new) == 1 and new[0] not in tables


@pytest.mark.slow
def test_studies_are_named_targets_that_reuse_the_default_tables(root, workdir):
    # closure study: 6 closure values x (2 speeds single wheel + soft pad + four wheels) growth
    # runs, 6 x 4 wear cases, one well-posedness job; the soft-pad points share the soft_pad
    # scenario's table. Stability: one job per case. Convergence: one job per value and reference
    # of every setting; the contact and growth points share the default table at 40 m/s.
    stab = yaml.safe_load((root / "config/stability.yaml").read_text())
    conv = yaml.safe_load((root / "config/convergence.yaml").read_text())
    n_conv = sum(len(s["values"]) + 1 for s in conv["settings"].values())
    out = snakemake(root, "-n", "closure_study", "stability", "convergence", cwd=workdir)
    assert out.returncode == 0, out.stderr
    c = job_counts(out.stdout)
    assert c["growth"] == 24 and c["closure_wear"] == 24 and c["closure_wellposedness"] == 1 and c["closure_aggregate"] == 1
    assert c["stability_case"] == len(stab["cases"]) and c["stability_table"] == 1
    assert n_conv == 26 and c["convergence_point"] == n_conv and c["convergence_aggregate"] == 1
    assert c["receptance"] == 4  # default at 20 and 40 m/s, soft_pad at 40 m/s, the four wheels of closure_class87 at 40 m/s


@pytest.mark.slow
def test_a_configfile_run_writes_under_its_own_name_and_leaves_the_defaults_untouched(root, workdir):
    # issue 23: `snakemake --configfile my_changes.yaml` wrote into results/ over the default results
    import hashlib

    defaults = {workdir / "results/figures/fig06.png": b"default figure", workdir / "results/data/fig06.nc": b"default data"}
    for path, content in defaults.items():
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(content)
    before = {p: hashlib.sha256(p.read_bytes()).hexdigest() for p in defaults}
    changes = workdir / "my_changes.yaml"
    changes.write_text("contact:\n  hertz_stiffness: 1.5e+9\n")
    out = snakemake(root, "-j1", "results/figures/fig06.png", "--configfile", str(changes), cwd=workdir)
    assert out.returncode == 0, out.stderr
    folder = re.search(r"it writes under (runs/my_changes-[0-9a-f]{8})/", out.stderr)
    assert folder, out.stderr
    assert {p: hashlib.sha256(p.read_bytes()).hexdigest() for p in defaults} == before
    run = workdir / folder.group(1)
    assert (run / "results/figures/fig06.png").stat().st_size > 10_000
    with xr.open_dataset(run / "results/data/fig06.nc") as ds:
        assert yaml.safe_load(ds.attrs["config"])["contact"]["hertz_stiffness"] == 1.5e9


@pytest.mark.slow
def test_one_off_configurations_of_the_same_file_name_get_their_own_folders(root, workdir):
    # issue 32: runs/<file name>/ was shared, so a second my.yaml found the first one's results
    # ("Nothing to be done") or wrote over them; the folder is keyed by the differing values
    def start_up_line(folder, stiffness):
        changes = workdir / folder / "my.yaml"
        changes.parent.mkdir()
        changes.write_text(f"contact:\n  hertz_stiffness: {stiffness}\n")
        out = snakemake(root, "-n", "results/figures/fig06.png", "--configfile", str(changes), cwd=workdir)
        assert out.returncode == 0, out.stderr[-2000:]
        line = re.search(r"one-off configuration \(differs from config/config\.yaml in (.*)\): it writes under (runs/my-[0-9a-f]{8})/", out.stderr)
        assert line, out.stderr[-2000:]
        assert job_counts(out.stdout) == {"halfspace_radiation": 1, "radiation_figures": 1}
        return line.group(1), line.group(2)

    keys_a, run_a = start_up_line("a", "1.5e+9")
    keys_b, run_b = start_up_line("b", "1.6e+9")
    keys_c, run_c = start_up_line("c", "1.5e+9")  # the first configuration again, from another folder
    assert keys_a == keys_b == keys_c == "contact.hertz_stiffness"
    assert run_a != run_b and run_c == run_a
    assert sorted(p.name for p in (workdir / "runs").iterdir()) == sorted({run_a[5:], run_b[5:]})


@pytest.mark.slow
def test_a_new_scenario_file_gets_its_figures_and_report_entries_from_one_command(root, workdir):
    # issue 23: a user's scenario gets the one-page overview (spectrum against wavelength beside the
    # default's, profiles, force), the band view and the 3-D plot from `snakemake -j2 study_<name>`,
    # and the HTML report lists them (reduced: one speed, 20,000 passages)
    (workdir / "config/scenarios/my_pad.yaml").write_text(
        "track:\n  pad:\n    stiffness: 2.0e+8\nspeeds: [40.0]\ngrowth:\n  passages: 20000\n")
    out = snakemake(root, "-j2", "study_my_pad", cwd=workdir)
    assert out.returncode == 0, out.stderr[-2000:]
    for suffix in ("overview", "bands", "3d"):
        assert (workdir / f"results/growth/my_pad/V40_{suffix}.png").stat().st_size > 10_000, suffix
    rep = snakemake(root, "--report", "report.html", "results/growth/my_pad/V40_overview.png", cwd=workdir)
    assert rep.returncode == 0, rep.stderr[-2000:]
    html = (workdir / "report.html").read_text(errors="replace")
    assert "V40_overview.png" in html and "my_pad" in html


@pytest.mark.slow
def test_cluster_profile_scales_growth_runtime_from_the_job_and_checks_status_with_squeue(root, workdir):
    # issue 23: growth asked a flat 30 min whatever the passages, wheels or nodes; and without an
    # accounting database the plugin's default status check (sacct) left the run waiting silently
    profile = yaml.safe_load((root / "profiles/slurm/config.yaml").read_text())
    assert profile["slurm-status-command"] == "squeue"
    assert "cpus_per_task" in profile["default-resources"]
    out = snakemake(root, "-n", "--profile", str(root / "profiles/slurm"), "results/figures/fig26.png", cwd=workdir)
    assert out.returncode == 0, out.stderr[-1500:]
    runtimes = {}
    for block in out.stdout.split("rule growth:")[1:]:
        name, speed = re.search(r"output: results/growth/(\w+)/V(\d+)\.nc", block).groups()
        runtimes[name, int(speed)] = int(re.search(r"runtime=(\d+)", block).group(1))
    # 10 updates of 0.5 s per wheel at 61 nodes, three times that plus 10 min: one wheel 10, four 11
    # (fig26 is now made with the other growth figures in one job, which also asks for other runs)
    assert {k: runtimes[k, 20] for k in ("default", "class87")} == {"default": 10, "class87": 11}


@pytest.fixture(scope="module")
def built(root, tmp_path_factory):
    """A working directory in which the default target is marked as built: every output of its
    jobs exists (empty) and `snakemake --touch` has recorded each job's metadata (its params among
    them), as a real run would. Nothing is computed."""
    work = tmp_path_factory.mktemp("built")
    shutil.copytree(root / "config", work / "config")
    summary = snakemake(root, "--summary", cwd=work)
    assert summary.returncode == 0, summary.stderr[-2000:]
    outputs = [line.split("\t")[0] for line in summary.stdout.splitlines()[1:] if "\t" in line]
    assert len(outputs) > 60, summary.stdout[-2000:]
    for path in outputs:
        (work / path).parent.mkdir(parents=True, exist_ok=True)
        (work / path).touch()
    touched = snakemake(root, "-j1", "-F", "--touch", cwd=work)
    assert touched.returncode == 0, touched.stderr[-2000:]
    return work


@pytest.mark.parametrize(
    "key, value, jobs",
    [
        # issue 32: these edits left Figs 2-6, 8, 22 and 9-19 untouched ("Nothing to be done")
        # half-space quadrature: Figs 2-6 (the forces' contact damping uses its own quadrature)
        ("numerics.halfspace.epsrel", 1.0e-9, {"halfspace_figures": 1, "halfspace_radiation": 1, "radiation_figures": 1}),
        # wheel mass: the forces and all that follows them, not the tracks' tables or the half-space
        ("wheels.mass", 1200.0, {"fig08": 1, "fig22": 1, "wear_cases": 1, "wear_figures": 1, "growth": 7, "growth_figures": 1, "growth_3d": 1}),
        # wear coefficient: wear and growth, not the forces (Figs 8, 22)
        ("wear.coefficient", 3.0e-9, {"wear_cases": 1, "wear_figures": 1, "growth": 7, "growth_figures": 1, "growth_3d": 1}),
        # issue 33: a figure key reruns the figure jobs that read it (Figs 9-19 and 20-27 are one job
        # each), not the wear cases or growth runs
        ("figures.wear.spectrum_max_wavenumber", 400.0, {"wear_figures": 1, "growth_figures": 1}),
        # issue 36: a track parameter names other (content-named) tables, so every job reading the default
        # track reruns: its tables (one wheel at 4 speeds, class87's four wheels at 2) and all after them
        # (soft_pad's own railpad keeps its table and growth run; Figs 24-25 are redrawn with the others)
        ("track.pad.stiffness", 4.0e8, {"receptance": 6, "fig08": 1, "fig22": 1, "wear_cases": 1, "wear_figures": 1, "growth": 6,
                                        "growth_figures": 1, "growth_3d": 1}),
    ],
)
@pytest.mark.slow
def test_a_config_edit_reruns_exactly_the_jobs_that_read_it(root, built, tmp_path, key, value, jobs):
    work = tmp_path / "work"
    shutil.copytree(built, work, symlinks=True)
    path = work / "config/config.yaml"
    cfg = yaml.safe_load(path.read_text())
    *parents, leaf = key.split(".")
    node = cfg
    for p in parents:
        node = node[p]
    assert node[leaf] != value
    node[leaf] = value
    path.write_text(yaml.safe_dump(cfg, sort_keys=False))
    out = snakemake(root, "-n", cwd=work)
    assert out.returncode == 0, out.stderr[-2000:]
    assert job_counts(out.stdout) == {**jobs, "all": 1}
    assert "Params have changed since last execution" in out.stdout


# Issue 32 (unclear cases): a target or study file the configuration would refuse stops at start-up
# with one line, not a KeyError, a cast error or a job the schema would refuse
@pytest.mark.parametrize("target, message", [
    ("results/receptance/default/V40_N100000.nc", r"target period N100000 is not allowed: it must lie in \[2, 256\] bays"),
    # issue 36: tables are named by their content; a scenario's name in their place says which path it is
    ("results/receptance/soft_pad/V40.nc", r"receptance tables are named by their content, not by a scenario: the table of "
                                          r"scenario 'soft_pad' at V40 is results/receptance/[0-9a-f]{10}/V40\.nc"),
    ("results/wear/default/V40_f1234.nc", r"target names the wear frequency f1234, which is not configured: the labels are"),
])
@pytest.mark.slow
def test_a_target_with_an_unknown_label_is_refused_in_one_line(root, workdir, target, message):
    out = snakemake(root, "-n", target, cwd=workdir)
    assert_stops_at_start_up(out, message)
    assert "KeyError" not in out.stderr and "Traceback" not in out.stderr


@pytest.mark.slow
def test_nan_in_the_convergence_study_is_refused_naming_the_key(root, workdir):
    # the study file is read beside the Snakefile: a copy of the workflow with its own file
    shutil.copytree(root / "workflow", workdir / "workflow")
    shutil.copy(root / "Snakefile", workdir / "Snakefile")
    f = workdir / "config/convergence.yaml"
    f.write_text(f.read_text().replace("reference: 1.0e-7", "reference: .nan"))
    out = snakemake(workdir, "-n", "results/figures/fig06.png", cwd=workdir)
    assert out.returncode != 0
    assert "config/convergence.yaml: settings.rtol.reference = nan is not allowed: it must be a finite number > 0." in out.stderr + out.stdout


@pytest.mark.parametrize("content, message", [
    (b"track:\n\tpad: 1\n", r"config/scenarios/bad\.yaml, line 2, column 1: not valid YAML: found character '\\t' that cannot start any token"),
    (bytes(range(128, 256)), r"config/scenarios/bad\.yaml: not a YAML text file \("),
])
@pytest.mark.slow
def test_a_scenario_file_that_is_not_yaml_is_named_with_its_line(root, workdir, content, message):
    # issue 45 (item 9): it stops only the targets that need it (study_bad), and says so once at start-up
    (workdir / "config/scenarios/bad.yaml").write_bytes(content)
    out = snakemake(root, "-n", "results/figures/fig06.png", cwd=workdir)
    assert out.returncode == 0, out.stderr[-2000:]
    notes = re.findall(r"^railgrowth: note: config/scenarios/bad\.yaml is not valid, so it is left out of this run: .*$",
                       out.stderr + out.stdout, re.M)
    assert len(notes) == 1 and re.search(message, notes[0]), out.stderr[-2000:]
    out = snakemake(root, "-n", "study_bad", cwd=workdir)
    assert_stops_at_start_up(out, r"target needs the scenario 'bad', which is left out of this run: .*" + message, workdir)


# ---------------------------------------------------------------- issue 36: report, table names, progress


def _mark_built(root, work, *targets):
    """Mark the outputs of ``targets`` as built without computing them, as the ``built`` fixture does:
    every output of their jobs exists (empty) and `snakemake --touch` records each job's metadata."""
    summary = snakemake(root, "--summary", *targets, cwd=work)
    assert summary.returncode == 0, summary.stderr[-2000:]
    outputs = [line.split("\t")[0] for line in summary.stdout.splitlines()[1:] if "\t" in line]
    for path in outputs:
        (work / path).parent.mkdir(parents=True, exist_ok=True)
        (work / path).touch()
    touched = snakemake(root, "-j1", "-F", "--touch", *targets, cwd=work)
    assert touched.returncode == 0, touched.stderr[-2000:]
    return outputs


@pytest.mark.slow
def test_the_report_builds_from_one_user_study_alone_and_lists_all_its_outputs(root, workdir):
    # issue 36: `snakemake --report` failed until every report figure was built (7 min for a user who
    # wanted only their study), and left out a study's growth-rate spectrum, CSVs and 3-D plots
    (workdir / "config/scenarios/my_pad.yaml").write_text("track:\n  pad:\n    stiffness: 2.0e+8\nspeeds: [40.0]\n")
    outputs = _mark_built(root, workdir, "study_my_pad", "results/spectrum/my_pad/rate_spectrum.png")
    assert not any(p.startswith("results/figures/") for p in outputs)  # no report figure is built
    rep = snakemake(root, "--report", "report.html", cwd=workdir)  # no target: whatever is built
    assert rep.returncode == 0, rep.stderr[-2000:]
    html = (workdir / "report.html").read_text(errors="replace")
    for name in ("V40_overview.png", "V40_bands.png", "V40_bands.csv", "V40_3d.png", "rate_spectrum.png", "summary.md"):
        assert name in html, name
    assert "my_pad" in html and "fig20.png" not in html
    # the named target gives the same report
    rep2 = snakemake(root, "--report", "report2.html", "report_all", cwd=workdir)
    assert rep2.returncode == 0, rep2.stderr[-2000:]
    assert "V40_3d.png" in (workdir / "report2.html").read_text(errors="replace")
    # and the --report=FILE spelling of the option is recognised as a report call too
    rep3 = snakemake(root, "--report=report3.html", cwd=workdir)
    assert rep3.returncode == 0, rep3.stderr[-2000:]
    assert "V40_3d.png" in (workdir / "report3.html").read_text(errors="replace")


@pytest.mark.slow
def test_adding_scenarios_reruns_no_job_of_another_scenario(root, built, tmp_path):
    # issue 36: adding a scenario renamed the shared receptance tables (named after the first scenario
    # holding a track) and changed the default tables' wheel offsets, so other studies reran. Here, in
    # a folder where the figure set is built: one scenario on soft_pad's track whose name comes first
    # (it took over the name of soft_pad's table), one with two wheels on the default track (it added
    # its spacing to the default tables), and one on the default track and wheels.
    work = tmp_path / "work"
    shutil.copytree(built, work, symlinks=True)
    scen = work / "config/scenarios"
    (scen / "a_soft.yaml").write_text((scen / "soft_pad.yaml").read_text() + "speeds: [40.0]\n")
    (scen / "a_bogie.yaml").write_text("wheels:\n  positions: [0.0, 3.3]\nspeeds: [40.0]\n")
    (scen / "a_creep.yaml").write_text("contact:\n  creepage: -0.002\nspeeds: [40.0]\n")
    same = snakemake(root, "-n", cwd=work)
    assert same.returncode == 0, same.stderr[-2000:]
    assert "Nothing to be done" in same.stdout + same.stderr, same.stdout[-3000:]
    out = snakemake(root, "-n", "all", "study_a_soft", "study_a_bogie", "study_a_creep", cwd=work)
    assert out.returncode == 0, out.stderr[-2000:]
    new = ("a_soft", "a_bogie", "a_creep")
    # the noise of a_bogie and a_creep (issue 56; a_soft's 70 MN/m pad has no CNOSSOS-EU pad class: no noise)
    assert job_counts(out.stdout) == {"growth": 3, "scenario_overview": 3, "growth_bands": 3, "growth_3d": 3, "growth_noise": 2,
                                      "receptance": 1, "study_a_soft": 1, "study_a_bogie": 1, "study_a_creep": 1}
    for rule, outs in job_outputs(out.stdout).items():
        if rule not in ("receptance",) and not rule.startswith("study_"):
            assert all(any(f"/{n}/" in o for n in new) for o in outs), (rule, outs)
    # the one new table is a_bogie's (two wheels); a_soft and a_creep read the tables already built
    assert re.search(r"receptance table results/receptance/[0-9a-f]{10}/V40\.nc: V = 40 m/s, offsets 0\.0 -3\.3 3\.3 m", out.stdout)
    assert "Params have changed" not in out.stdout and "Input files updated by another job: results/growth/default" not in out.stdout


@pytest.mark.slow
def test_a_table_job_writes_progress_lines_to_its_log(root, workdir):
    # issue 36: the table and spectrum jobs were silent for minutes; a tiny problem (K = 33, N = 4)
    for f in (workdir / "config/scenarios").glob("*.yaml"):
        f.unlink()
    (workdir / "config/scenarios/tiny.yaml").write_text(
        "numerics:\n  track:\n    harmonics: 33\nroughness:\n  bays: 4\nspeeds: [40.0]\n")
    plan = snakemake(root, "-n", "results/growth/tiny/V40.nc", cwd=workdir)
    tables = table_paths(plan.stdout)
    assert len(tables) == 1 and tables[0].endswith("V40_N4.nc"), plan.stdout[-2000:]
    run = snakemake(root, "-j1", tables[0], cwd=workdir)
    assert run.returncode == 0, run.stderr[-2000:]
    log = (workdir / tables[0].replace("results/", "logs/").replace(".nc", ".log")).read_text()
    lines = re.findall(r"^(\d) of 3 tables \(Bloch fraction (\d)/4, \d+ nodes\), \d+ s elapsed, about \d+ s left$", log, re.M)
    assert lines == [("1", "0"), ("2", "1"), ("3", "2")], log


_TEE_CHILD = """
import sys
from rail.setup.progress import Tee
log = open(sys.argv[1], "w")
sys.stderr = log
t = Tee(log, "growth default V40")
print("resuming from x.npz: 10000 of 40000 passages done", file=t, flush=True)
for done in (20000, 30000, 40000):
    print(f"{done} of 40000 passages, 825 passages/s, 1 s left", file=t, flush=True)
t.close()
"""


def _under_a_terminal(root, tmp_path, stderr_to_file):
    """Run _TEE_CHILD with a pseudo-terminal as its controlling terminal (of no window size, as
    under `script` or an agent's console); its stderr on that terminal or in a file, as Snakemake's
    when run as `snakemake ... 2> run.txt`. Returns (what the terminal showed, the log, the stderr file)."""
    import os
    import pty

    log, err = tmp_path / "job.log", tmp_path / "stderr.txt"
    pid, fd = pty.fork()
    if pid == 0:  # the child: a new session whose controlling terminal is the pty
        try:
            if stderr_to_file:
                os.dup2(os.open(err, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644), 2)
            env = {**os.environ, "PYTHONPATH": str(root)}
            os.execve(sys.executable, [sys.executable, "-c", _TEE_CHILD, str(log)], env)
        finally:
            os._exit(1)
    shown = b""
    while True:
        try:
            chunk = os.read(fd, 4096)
        except OSError:  # EIO: the child closed the terminal
            break
        if not chunk:
            break
        shown += chunk
    _, status = os.waitpid(pid, 0)
    assert os.waitstatus_to_exitcode(status) == 0, shown.decode(errors="replace")
    return shown.decode(errors="replace"), log.read_text(), err.read_text() if err.exists() else ""


@pytest.mark.parametrize("stderr_to_file", [False, True], ids=["stderr-on-terminal", "stderr-in-a-file"])
def test_growth_bar_shows_on_a_terminal_of_no_size_and_when_stderr_is_redirected(root, tmp_path, stderr_to_file):
    # issue 36: "under a terminal the growth bar did not show". Two causes: a terminal reporting no
    # window size (0 columns: tqdm drew an empty bar), and Snakemake's stderr not being the terminal
    # (the bar was then switched off although the user watches the terminal, /dev/tty)
    shown, log, err = _under_a_terminal(root, tmp_path, stderr_to_file)
    assert "40000/40000" in shown and "100%" in shown, shown  # the bar, drawn and completed
    assert "[growth default V40] resuming from x.npz" in shown
    assert log.splitlines() == ["resuming from x.npz: 10000 of 40000 passages done",
                                "20000 of 40000 passages, 825 passages/s, 1 s left",
                                "30000 of 40000 passages, 825 passages/s, 1 s left",
                                "40000 of 40000 passages, 825 passages/s, 1 s left"]  # the log keeps every line
    assert "40000/40000" not in err  # nothing of the bar in a redirected stderr


def test_table_progress_lines_count_to_the_end_and_leave_the_tables_unchanged():
    # the progress callback of the table computation reports every step and changes no number
    import numpy as np
    from test_growth import track

    from rail import moving

    lines = []
    quiet = moving.bloch_tables(track(), 40.0, 8, 4, (0.0, 3.3), 1e-4)
    told = moving.bloch_tables(track(), 40.0, 8, 4, (0.0, 3.3), 1e-4, progress=lines.append)
    assert all(np.array_equal(a.A, b.A) for a, b in zip(quiet, told))
    assert [re.match(r"(\d) of 3 tables \(Bloch fraction (\d)/4, \d+ nodes\)$", x).groups() for x in lines] == [
        ("1", "0"), ("2", "1"), ("3", "2")]
    blocks = []
    one = moving.receptance_table(track(), 40.0, 8, (0.0,), 1e-4, progress=blocks.append)
    assert np.array_equal(one.A, moving.receptance_table(track(), 40.0, 8, (0.0,), 1e-4).A)
    done = [re.match(r"(\d+) of (\d+) node blocks", x).groups() for x in blocks if "node blocks" in x]
    assert done[0][0] == "0" and done[-1][0] == done[-1][1] and len(done) == int(done[-1][1]) + 1
    assert any(x.startswith("wavenumber rule: refinement pass 1,") for x in blocks)


def test_table_names_follow_the_content_only():
    from rail.setup.tables import table_key

    part = {"track": {"pad": {"stiffness": 3.5e8}, "sleeper": {"spacing": 0.6}}, "numerics": {"track": {"harmonics": 64}}}
    key = table_key(part, [0.0, 3.3, -3.3])
    assert re.fullmatch(r"[0-9a-f]{10}", key)
    assert table_key({"numerics": part["numerics"], "track": part["track"]}, [-3.3, 3.3, -0.0, 0.0]) == key  # order, -0
    assert table_key(part, [0.0]) != key  # other wheels
    other = {"track": {"pad": {"stiffness": 3.6e8}, "sleeper": {"spacing": 0.6}}, "numerics": part["numerics"]}
    assert table_key(other, [0.0, 3.3, -3.3]) != key  # a track parameter
    with pytest.raises(ValueError, match=r"offsets = 'x' is not allowed: it must be a sequence of numbers in m"):
        table_key(part, "x")


def test_no_terminal_no_bar(root, tmp_path):
    # a cluster job or a run without a controlling terminal: the log only, nothing else opened
    log = tmp_path / "job.log"
    child = _TEE_CHILD.replace('t = Tee(log, "growth default V40")\n', 't = Tee(log, "growth default V40")\nassert t.terminal is None\n')
    assert child != _TEE_CHILD
    out = subprocess.run([sys.executable, "-c", child, str(log)], capture_output=True,
                         text=True, start_new_session=True, env={"PYTHONPATH": str(root), "PATH": ""}, timeout=60)
    assert out.returncode == 0, out.stderr
    assert "40000/40000" not in out.stderr + out.stdout and len(log.read_text().splitlines()) == 4


def test_short_drawing_and_summing_jobs_are_not_queued_behind_long_ones(root):
    # issue 57, item 8: a 9 s plotting job waited 33 minutes behind long jobs under -j2. Every local
    # rule (a figure, a table, a summary of finished jobs) and the two short summaries that are not local
    # have the kernels' priority, above every table and growth run (their priorities stay below it)
    import re

    from rail.setup.targets import PRIORITY_KERNELS, PRIORITY_TABLES

    rules = {}
    for f in sorted((root / "workflow/rules").glob("*.smk")):
        for block in re.split(r"(?m)^(?=rule \w+:)", f.read_text()):
            if m := re.match(r"rule (\w+):", block):
                rules[m.group(1)] = block
    short = {name for name, b in rules.items() if re.search(r"(?m)^    localrule: True", b)} | {"fleet_rate_spectrum", "irregular_summary"}
    assert {"growth_figures", "wear_figures", "rate_spectrum_map", "fig08", "sweep_bands"} <= short
    for name in sorted(short):
        assert re.search(r"(?m)^    priority: PRIORITY_KERNELS\b", rules[name]), name
    for name in ("growth", "fleet_growth", "rate_spectrum_speed", "fleet_class_spectrum", "receptance", "receptance_bloch"):
        assert not re.search(r"(?m)^    priority: PRIORITY_KERNELS\b", rules[name]), name
    assert PRIORITY_TABLES < PRIORITY_KERNELS  # the tables' (and below them the growth runs') priorities stay below
