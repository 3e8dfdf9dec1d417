# How much the corrugation prediction depends on the tangential contact closure (docs/contact.md):
# named target closure_study (README; the loop over config/studies/ in spectrum.smk). The growth runs are
# the points of the sweeps of config/studies/closure_study.yaml (Plan.closure_studies).


rule closure_wear:
    """One passage over a harmonic roughness (Figs 12-19) with closure value s."""
    input:
        table=table_file("default", config["figures"]["wear"]["speed"]),
    output:
        "results/closure/wear/s{s}_f{freq}.nc",
    params:
        code=code("wear_case.py"),
        frequencies=lambda wildcards: [wear_frequency(wildcards)],
        cfg=closure_wear_config,
    resources:
        mem_mb=1000,
        runtime=10,
    log:
        "logs/closure/wear_s{s}_f{freq}.log",
    benchmark:
        "benchmarks/closure/wear_s{s}_f{freq}.tsv"
    script:
        "../scripts/wear_case.py"


rule closure_wellposedness:
    """Perturbation growth per patch transit of every closure value on three grids."""
    input:
        kernels=kernels("march"),
    output:
        "results/closure/wellposedness.nc",
    params:
        code=code("closure_wellposedness.py"),
        cfg=default_physics("figures.wear.speed"),
        values=PLAN.closure_values(),
        nodes=PLAN.closure["wellposedness_nodes"],
    resources:
        mem_mb=900,
        runtime=15,
    log:
        "logs/closure/wellposedness.log",
    benchmark:
        "benchmarks/closure/wellposedness.tsv"
    script:
        "../scripts/closure_wellposedness.py"


rule closure_aggregate:
    """The closure study's dataset, spectra figures and conclusions table."""
    priority: PRIORITY_KERNELS  # a short drawing or summing job: not queued behind long jobs (issue 57)
    localrule: True
    input:
        PLAN.closure_inputs()[0] if PLAN.closure_values() else [],
    output:
        data="results/closure/closure.nc",
        spectra=report("results/closure/spectra.png", caption="../report/closure.rst", category="Closure sensitivity study"),
        wear=report("results/closure/wear_spectra.png", caption="../report/closure.rst", category="Closure sensitivity study"),
        table="results/closure/conclusions.md",
        html=report("results/closure/conclusions.html", caption="../report/closure.rst", category="Closure sensitivity study"),
    params:
        code=code("closure_aggregate.py"),
        cfg=default_physics("figures.wear.spectrum_max_wavenumber"),
        meta=PLAN.closure_inputs()[1] if PLAN.closure_values() else [],
    resources:
        mem_mb=400,
        runtime=5,
    log:
        "logs/closure/aggregate.log",
    benchmark:
        "benchmarks/closure/aggregate.tsv"
    script:
        "../scripts/closure_aggregate.py"
