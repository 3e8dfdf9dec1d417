# Sweep studies: a scenario with a "sweep:" expands into one growth run per grid point.


rule sweep_aggregate:
    """One dataset with a dimension per swept key, and a map of the fastest growth over the grid."""
    priority: PRIORITY_KERNELS  # a short drawing or summing job: not queued behind long jobs (issue 57)
    localrule: True
    input:
        sweep_runs,
    output:
        data="results/sweeps/{study}.nc",
        figure=report("results/sweeps/{study}.png", caption="../report/sweep.rst", category="Sweep studies"),
    params:
        code=code("sweep_aggregate.py"),
        cfg={},  # drawn from the runs alone, each of which records its configuration
        swept=sweep_keys,
        grid=sweep_values,
        indices=sweep_indices,
        units=sweep_units,
    resources:
        mem_mb=400,
        runtime=5,
    log:
        "logs/sweeps/{study}.log",
    benchmark:
        "benchmarks/sweeps/{study}.tsv"
    script:
        "../scripts/sweep_aggregate.py"


rule sweep_bands:
    """Growth rate per one-third-octave band over the grid of a sweep study (map over band and key)."""
    priority: PRIORITY_KERNELS  # a short drawing or summing job: not queued behind long jobs (issue 57)
    localrule: True
    input:
        sweep_runs,
    output:
        data="results/sweeps/{study}_bands.nc",
        figure=report("results/sweeps/{study}_bands.png", caption="../report/sweep_bands.rst", category="Roughness bands (EN 15610 form)"),
    params:
        code=code("sweep_bands.py"),
        cfg=config_part(("track", "numerics.track", "figures.bands")),
        swept=sweep_keys,
        grid=sweep_values,
        indices=sweep_indices,
        units=sweep_units,
    resources:
        mem_mb=400,
        runtime=5,
    log:
        "logs/sweeps/{study}_bands.log",
    benchmark:
        "benchmarks/sweeps/{study}_bands.tsv"
    script:
        "../scripts/sweep_bands.py"


rule sweeps:
    """Named target: every sweep study in config/scenarios/."""
    input:
        PLAN.sweep_targets(),
