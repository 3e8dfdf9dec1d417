# Section 3: elastic half-space, radiated power and contact-spring damping (Figs 2-6).


rule halfspace_figure:
    """Figs 2-4: integrand of eq (14), beta G (eq 15), displacement against Boussinesq."""
    output:
        data="results/data/fig{nn}.nc",
        figure=report(
            "results/figures/fig{nn}.png",
            caption="../report/halfspace_figure.rst",
            category="Section 3: half-space",
        ),
    wildcard_constraints:
        nn="02|03|04",
    params:
        code=code("halfspace_figure.py"),
        cfg=config_part(HALFSPACE_KEYS),
    resources:
        mem_mb=900,
        runtime=5,
    log:
        "logs/fig{nn}.log",
    benchmark:
        "benchmarks/figures/fig{nn}.tsv"
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


rule radiation_figure:
    """Figs 5-6: radiated power and contact-spring loss factor against frequency."""
    input:
        "results/halfspace/radiation.nc",
    output:
        data="results/data/fig{nn}.nc",
        figure=report(
            "results/figures/fig{nn}.png",
            caption="../report/radiation_figure.rst",
            category="Section 3: half-space",
        ),
    wildcard_constraints:
        nn="05|06",
    params:
        code=code("radiation_figure.py"),
        cfg=config_part(HALFSPACE_KEYS),
    resources:
        mem_mb=400,
        runtime=5,
    log:
        "logs/fig{nn}.log",
    benchmark:
        "benchmarks/figures/fig{nn}.tsv"
    script:
        "../scripts/radiation_figure.py"
