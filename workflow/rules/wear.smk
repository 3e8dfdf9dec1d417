# Sections 4.3 and 5: tangential contact and wear of one passage (Figs 9-19).


rule wear_case:
    """One wheel passage over a harmonic roughness: contact and wear along the bay."""
    input:
        kernels=kernels("march"),
        table="results/receptance/{track}/V{speed}.nc",
    output:
        "results/wear/{track}/V{speed}_f{freq}.nc",
    wildcard_constraints:
        track="default",
    params:
        code=code("wear_case.py"),
        frequency=wear_frequency,
        cfg=config_part(WEAR_CASE_KEYS),
    resources:
        mem_mb=1000,
        runtime=10,
    log:
        "logs/wear/{track}/V{speed}_f{freq}.log",
    benchmark:
        "benchmarks/wear/{track}/V{speed}_f{freq}.tsv"
    script:
        "../scripts/wear_case.py"


rule wear_figure:
    """Figs 9-19 from the wear cases."""
    input:
        wear_case_file,
    output:
        data="results/data/fig{nn}.nc",
        figure=report("results/figures/fig{nn}.png", caption="../report/wear_figure.rst", category="Sections 4.3 and 5: contact and wear"),
    wildcard_constraints:
        nn="09|1[0-9]",
    params:
        code=code("wear_figure.py"),
        cfg=wear_figure_config,
    resources:
        mem_mb=400,
        runtime=5,
    log:
        "logs/fig{nn}.log",
    benchmark:
        "benchmarks/figures/fig{nn}.tsv"
    script:
        "../scripts/wear_figure.py"
