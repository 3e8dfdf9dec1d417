# Sections 4.3 and 5: tangential contact and wear of one passage (Figs 9-19).


rule wear_cases:
    """One wheel passage over a harmonic roughness at each configured frequency (figures.wear.frequencies,
    the cases of Figs 9-19): contact and wear along the bay. One job for all of them: each passage
    takes about 1 s CPU, a job's start-up (imports, loading the compiled march) about 4 s."""
    input:
        kernels=kernels("march"),
        table=wear_table,
    output:
        expand("results/wear/{{track}}/V{{speed}}_f{freq}.nc", freq=[wear_frequency_label(f) for f in config["figures"]["wear"]["frequencies"]]),
    wildcard_constraints:
        track="default",
        speed="[^_/]+",
    params:
        code=code("wear_case.py"),
        frequencies=[float(f) for f in config["figures"]["wear"]["frequencies"]],
        cfg=config_part(WEAR_CASE_KEYS),
    resources:
        mem_mb=1000,
        runtime=10,
    log:
        "logs/wear/{track}/V{speed}.log",
    benchmark:
        "benchmarks/wear/{track}/V{speed}.tsv"
    script:
        "../scripts/wear_case.py"


rule wear_case:
    """A wear case at a frequency label that wear_cases does not make: it names the configured labels
    (wear_frequency) and stops, at planning."""
    input:
        kernels=kernels("march"),
        table=wear_table,
    output:
        "results/wear/{track}/V{speed}_f{freq}.nc",
    wildcard_constraints:
        track="default",
    params:
        code=code("wear_case.py"),
        frequencies=lambda wildcards: [wear_frequency(wildcards)],
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


ruleorder: wear_cases > wear_case


rule wear_figures:
    """Figs 9-19 from the wear cases, in one job (a job's start-up, 3 s CPU, is six times the drawing
    of one figure). Each figure's dataset records the configuration it reads (wear_figure_config)."""
    priority: PRIORITY_KERNELS  # a short drawing or summing job: not queued behind long jobs (issue 57)
    localrule: True
    input:
        PLAN.wear_figure_cases(),
    output:
        data=expand("results/data/fig{nn}.nc", nn=WEAR_FIGURES),
        figure=[
            report(f"results/figures/fig{nn}.png", caption=f"../report/fig{nn}.rst", category="Sections 4.3 and 5: contact and wear")
            for nn in WEAR_FIGURES
        ],
    params:
        code=code("wear_figure.py"),
        cases={nn: PLAN.wear_case_file(nn) for nn in WEAR_FIGURES},
        cfg={nn: PLAN.wear_figure_config(nn) for nn in WEAR_FIGURES},
    resources:
        mem_mb=500,
        runtime=5,
    log:
        "logs/figures/wear_figures.log",
    benchmark:
        "benchmarks/figures/wear_figures.tsv"
    script:
        "../scripts/wear_figure.py"
