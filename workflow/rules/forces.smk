# Section 4.2: normal wheel/rail forces (Figs 8 and 22).


rule fig08:
    """Fig. 8: one wheel at 40 m/s over a 10 um roughness at 1000 Hz."""
    priority: PRIORITY_KERNELS  # a short drawing or summing job: not queued behind long jobs (issue 57)
    localrule: True
    input:
        table=table_file("default", config["figures"]["fig08"]["speed"]),
    output:
        data="results/data/fig08.nc",
        figure=report("results/figures/fig08.png", caption="../report/fig08.rst", category="Section 4.2: wheel/rail forces"),
    params:
        code=code("forces_figure.py"),
        cfg=config_part(FORCE_KEYS + ("figures.fig08",)),
    resources:
        mem_mb=400,
        runtime=5,
    log:
        "logs/fig08.log",
    benchmark:
        "benchmarks/figures/fig08.tsv"
    script:
        "../scripts/forces_figure.py"


rule fig22:
    """Fig. 22: one wheel over a smooth rail at 20 and 40 m/s (parametric excitation)."""
    priority: PRIORITY_KERNELS  # a short drawing or summing job: not queued behind long jobs (issue 57)
    localrule: True
    input:
        tables=[table_file("default", v) for v in config["figures"]["fig22"]["speeds"]],
    output:
        data="results/data/fig22.nc",
        figure=report("results/figures/fig22.png", caption="../report/fig22.rst", category="Section 4.2: wheel/rail forces"),
    params:
        code=code("forces_figure.py"),
        cfg=config_part(FORCE_KEYS + ("figures.fig22",)),
    resources:
        mem_mb=400,
        runtime=5,
    log:
        "logs/fig22.log",
    benchmark:
        "benchmarks/figures/fig22.tsv"
    script:
        "../scripts/forces_figure.py"
