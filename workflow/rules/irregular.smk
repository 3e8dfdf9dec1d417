# Irregular track (issue 34): supports that vary over a cell of N bays (rail/cell.py, docs/track.md
# "A cell of N bays"). Named target irregular_track (README; the loop over config/studies/ in spectrum.smk):
# the cases of config/studies/irregular_track.yaml each beside its uniform track, and the random-track ensemble
# (the roles of its summary: Plan.irregular_study).

import re

IRREGULAR_CASES = PLAN.irregular_cases()  # speed: rail.setup.plan.IRREGULAR_SPEED
IRREGULAR_UNIFORM = PLAN.irregular_study().get("uniform")


rule irregular_case:
    """One irregular case beside the uniform track: receptance above each support, force along the
    cell over the smooth rail, roughness after the run, growth-rate spectrum."""
    input:
        growth=f"results/growth/{{case}}/V{IRREGULAR_SPEED}.nc",
        growth_uniform=f"results/growth/{IRREGULAR_UNIFORM}/V{IRREGULAR_SPEED}.nc",
        spectrum=f"results/spectrum/{{case}}/V{IRREGULAR_SPEED}.nc",
        spectrum_uniform=f"results/spectrum/{IRREGULAR_UNIFORM}/V{IRREGULAR_SPEED}.nc",
    output:
        data="results/irregular/{case}.nc",
        figure=report("results/irregular/{case}.png", caption="../report/irregular_case.rst", category="Irregular track"),
    wildcard_constraints:
        case="|".join(map(re.escape, IRREGULAR_CASES)) or "(?!)",  # the study file's cases, not a name prefix
    params:
        code=code("irregular_case.py"),
        cfg=lambda w: {"case": config_part(("track",), SCENARIOS[w.case]),
                       "uniform": config_part(("track", "numerics.track"), SCENARIOS[IRREGULAR_UNIFORM])},
        speed=float(IRREGULAR_SPEED),
    log:
        "logs/irregular/{case}.log",
    benchmark:
        "benchmarks/irregular/{case}.tsv"
    resources:
        mem_mb=800,
        runtime=20,
    script:
        "../scripts/irregular_case.py"


rule irregular_summary:
    """The pinned-pinned band and the loudest band after the run: uniform track, named cases and the
    random-track ensemble (median and range over seeds per spread)."""
    priority: PRIORITY_KERNELS  # a short drawing or summing job: not queued behind long jobs (issue 57)
    input:
        cases=expand(f"results/growth/{{case}}/V{IRREGULAR_SPEED}.nc", case=IRREGULAR_CASES),
        uniform=f"results/growth/{IRREGULAR_UNIFORM}/V{IRREGULAR_SPEED}.nc",
        random=[f"results/growth/{name}/V{IRREGULAR_SPEED}.nc" for name in PLAN.irregular_random_points()],
    output:
        data="results/irregular/summary.nc",
        figure=report("results/irregular/summary.png", caption="../report/irregular_summary.rst", category="Irregular track"),
        table="results/irregular/summary.md",
    params:
        code=code("irregular_summary.py"),
        cfg={name: config_part(("track",), SCENARIOS[name]) for name in PLAN.irregular_random_points()},
        case_cfg={c: config_part(("track",), SCENARIOS[c]) for c in IRREGULAR_CASES},
        uniform_cfg=lambda w: config_part(("track", "numerics.track"), SCENARIOS[IRREGULAR_UNIFORM]),
        spreads={name: SCENARIOS[name]["track"]["cell"]["random"].get("spacing", 0.0) for name in PLAN.irregular_random_points()},
        speed=float(IRREGULAR_SPEED),
    log:
        "logs/irregular/summary.log",
    benchmark:
        "benchmarks/irregular/summary.tsv"
    resources:
        mem_mb=600,
        runtime=5,
    script:
        "../scripts/irregular_summary.py"
