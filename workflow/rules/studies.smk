# Numerical studies (named targets, not part of the default run; README):
#   stability    - the stability suite of config/stability.yaml: outcome table
#   convergence  - error of the figure quantities against run time for every numerical setting

STABILITY = load_yaml(workflow.source_path("../../config/stability.yaml"))


rule stability_case:
    """One case of the stability suite: a checked result or a clear error (never NaN)."""
    output:
        "results/stability/cases/{case}.json",
    params:
        code=code("growth", "present", "stability"),
        case=lambda w: {**STABILITY["defaults"], **STABILITY["cases"][w.case]},
    wildcard_constraints:
        case="|".join(STABILITY["cases"]),
    resources:
        mem_mb=1500,
        runtime=15,
    log:
        "logs/stability/{case}.log",
    script:
        "../scripts/stability_case.py"


rule stability_table:
    """Outcome table of the stability suite (netCDF, markdown and HTML for the report)."""
    input:
        expand("results/stability/cases/{case}.json", case=list(STABILITY["cases"])),
    output:
        data="results/stability/outcomes.nc",
        table="results/stability/outcomes.md",
        html=report("results/stability/outcomes.html", caption="../report/stability.rst", category="Numerical studies"),
    params:
        code=code("track", "present", "studies"),
        expect={name: c["expect"] for name, c in STABILITY["cases"].items()},
    resources:
        mem_mb=1000,
        runtime=10,
    log:
        "logs/stability/table.log",
    script:
        "../scripts/stability_table.py"


rule stability:
    """Named target: the stability suite."""
    input:
        rules.stability_table.output,
