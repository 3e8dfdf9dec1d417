# Numerical studies (named targets, not part of the default run; README):
#   stability    - the stability suite of config/stability.yaml: outcome table
#   convergence  - error of the figure quantities against run time for every numerical setting

rule stability_case:
    """One case of the stability suite: a checked result or a clear error (never NaN)."""
    input:
        kernels=kernels("march"),
    output:
        "results/stability/cases/{case}.json",
    params:
        code=code("stability_case.py"),
        cfg=lambda w: PLAN.stability_config(w.case),  # what the case reads of the configuration it is merged onto
        case=lambda w: {**PLAN.stability["defaults"], **PLAN.stability["cases"][w.case]},
    wildcard_constraints:
        case="|".join(PLAN.stability["cases"]),
    resources:
        mem_mb=1800,
        runtime=15,
    log:
        "logs/stability/{case}.log",
    benchmark:
        "benchmarks/stability/{case}.tsv"
    script:
        "../scripts/stability_case.py"


rule stability_table:
    """Outcome table of the stability suite (netCDF, markdown and HTML for the report)."""
    priority: PRIORITY_KERNELS  # a short drawing or summing job: not queued behind long jobs (issue 57)
    localrule: True
    input:
        expand("results/stability/cases/{case}.json", case=list(PLAN.stability["cases"])),
    output:
        data="results/stability/outcomes.nc",
        table="results/stability/outcomes.md",
        html=report("results/stability/outcomes.html", caption="../report/stability.rst", category="Numerical studies"),
    params:
        code=code("stability_table.py"),
        cfg=default_physics(),
        expect={name: c["expect"] for name, c in PLAN.stability["cases"].items()},
    resources:
        mem_mb=300,
        runtime=10,
    log:
        "logs/stability/table.log",
    benchmark:
        "benchmarks/stability/table.tsv"
    script:
        "../scripts/stability_table.py"


rule stability:
    """Named target: the stability suite."""
    input:
        rules.stability_table.output,


rule convergence_point:
    """One point of the convergence study (a figure quantity at one value of one setting)."""
    input:
        unpack(convergence_table),
        kernels=kernels("march"),
    output:
        "results/convergence/points/{setting}/{value}.nc",
    params:
        code=code("convergence_point.py"),
        cfg=default_physics("figures.wear.amplitude"),
        study=PLAN.convergence,
        value=lambda w: PLAN.convergence_values[(w.setting, w.value)],
    wildcard_constraints:
        setting="|".join(PLAN.convergence["settings"]),
    resources:
        mem_mb=3200,
        runtime=30,
    log:
        "logs/convergence/{setting}_{value}.log",
    benchmark:
        "benchmarks/convergence/{setting}_{value}.tsv"
    script:
        "../scripts/convergence_point.py"


rule convergence_aggregate:
    """Error against CPU time for every setting: dataset, log-log figure and summary table."""
    priority: PRIORITY_KERNELS  # a short drawing or summing job: not queued behind long jobs (issue 57)
    localrule: True
    input:
        PLAN.convergence_points(),
    output:
        data="results/convergence/convergence.nc",
        figure=report("results/convergence/error_vs_time.png", caption="../report/convergence.rst", category="Numerical studies"),
        table="results/convergence/summary.md",
        html=report("results/convergence/summary.html", caption="../report/convergence.rst", category="Numerical studies"),
    params:
        code=code("convergence_aggregate.py"),
        cfg=default_physics(),
        study=PLAN.convergence,
    resources:
        mem_mb=300,
        runtime=5,
    log:
        "logs/convergence/aggregate.log",
    benchmark:
        "benchmarks/convergence/aggregate.tsv"
    script:
        "../scripts/convergence_aggregate.py"


rule convergence:
    """Named target: the convergence study."""
    input:
        rules.convergence_aggregate.output,
