# Section 3: elastic half-space, radiated power and contact-spring damping (Figs 2-6).


rule halfspace_figures:
    """Figs 2-4: integrand of eq (14), beta G (eq 15), displacement against Boussinesq. One job for
    the three: a job's start-up (imports, 3 s CPU) costs more than drawing Figs 2 and 3."""
    output:
        data=expand("results/data/fig{nn}.nc", nn=HALFSPACE_FIGURES[:3]),
        figure=[
            report(f"results/figures/fig{nn}.png", caption=f"../report/fig{nn}.rst", category="Section 3: half-space")
            for nn in HALFSPACE_FIGURES[:3]
        ],
    params:
        code=code("halfspace_figure.py"),
        figures=HALFSPACE_FIGURES[:3],
        cfg=config_part(HALFSPACE_KEYS),
    resources:
        mem_mb=900,
        runtime=5,
    log:
        "logs/figures/halfspace_figures.log",
    benchmark:
        "benchmarks/figures/halfspace_figures.tsv"
    script:
        "../scripts/halfspace_figure.py"


rule halfspace_radiation:
    """Im w0(0), radiated power and contact loss factor over frequency (feeds Figs 5-6)."""
    output:
        "results/halfspace/radiation.nc",
    params:
        code=code("halfspace_radiation.py"),
        cfg=config_part(HALFSPACE_KEYS),
    resources:
        mem_mb=800,
        runtime=5,
    log:
        "logs/halfspace_radiation.log",
    benchmark:
        "benchmarks/halfspace/radiation.tsv"
    script:
        "../scripts/halfspace_radiation.py"


rule radiation_figures:
    """Figs 5-6: radiated power and contact-spring loss factor against frequency (one job for both)."""
    priority: PRIORITY_KERNELS  # a short drawing or summing job: not queued behind long jobs (issue 57)
    localrule: True
    input:
        "results/halfspace/radiation.nc",
    output:
        data=expand("results/data/fig{nn}.nc", nn=HALFSPACE_FIGURES[3:]),
        figure=[
            report(f"results/figures/fig{nn}.png", caption=f"../report/fig{nn}.rst", category="Section 3: half-space")
            for nn in HALFSPACE_FIGURES[3:]
        ],
    params:
        code=code("radiation_figure.py"),
        figures=HALFSPACE_FIGURES[3:],
        cfg=config_part(HALFSPACE_KEYS),
    resources:
        mem_mb=400,
        runtime=5,
    log:
        "logs/figures/radiation_figures.log",
    benchmark:
        "benchmarks/figures/radiation_figures.tsv"
    script:
        "../scripts/radiation_figure.py"
