# Sweep studies: a scenario with a "sweep:" expands into one growth run per grid point.


rule sweep_aggregate:
    """One dataset with a dimension per swept key, and a map of the fastest growth over the grid."""
    input:
        sweep_runs,
    output:
        data="results/sweeps/{study}.nc",
        figure=report("results/sweeps/{study}.png", caption="../report/sweep.rst", category="Sweep studies"),
    params:
        code=code("sweep_aggregate.py"),
        swept=sweep_keys,
        grid=sweep_values,
        indices=sweep_indices,
    resources:
        mem_mb=500,
        runtime=5,
    log:
        "logs/sweeps/{study}.log",
    script:
        "../scripts/sweep_aggregate.py"


rule sweeps:
    """Named target: every sweep study in config/scenarios/."""
    input:
        sweep_targets(),
