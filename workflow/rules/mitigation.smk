# Which mitigation reduces the band near pinned-pinned (issue 55, rail.studies.mitigation; docs/field.md "Mitigation"):
# the summary of config/studies/track_mitigation.yaml, its named target mitigation (the loop over config/studies/ in
# spectrum.smk builds each case's spectrum and settled spectrum first). Its roles: spread, the default track's cases at
# three speeds each; dampers, soft_pad, stiff_pad and trailer, a case each at one of those nominal speeds.

from rail.setup.study_files import study_summary

MITIGATION = {k: v for k, v in study_summary(PLAN.studies, "mitigation").items() if k not in ("kind", "study")}


rule mitigation_summary:
    input:
        lambda w: [f"results/spectrum/{n}/rate_spectrum.nc" for role in MITIGATION.values() for n in role if n in SCENARIOS],
    output:
        data="results/mitigation/mitigation.nc",
        figure=report("results/mitigation/mitigation.png", caption="../report/mitigation.rst", category="Mitigation"),
        csv=report("results/mitigation/mitigation.csv", caption="../report/mitigation.rst", category="Mitigation"),
        summary=report("results/mitigation/mitigation.md", caption="../report/mitigation.rst", category="Mitigation"),
    log:
        "logs/mitigation/mitigation.log",
    benchmark:
        "benchmarks/mitigation/mitigation.tsv"
    """The band's peak, width and growth per mitigation, speed spread and driven share, and the time from a ground rail
    to the limit under the wheels' source (CSV, markdown, netCDF, figure)."""
    priority: PRIORITY_KERNELS  # a short summing and drawing job: not queued behind long jobs (issue 57)
    localrule: True
    resources:
        mem_mb=500,
        runtime=5,
    params:
        code=code("mitigation.py"),
        roles={role: [n for n in names if n in SCENARIOS] for role, names in MITIGATION.items()},
        speeds={n: SCENARIOS[n]["figures"]["rate_spectrum"]["speeds"] for names in MITIGATION.values() for n in names if n in SCENARIOS},
        cfg=lambda w: next((SCENARIOS[n] for n in MITIGATION.get("spread", []) if n in SCENARIOS), PLAN.config),
    script:
        "../scripts/mitigation.py"
