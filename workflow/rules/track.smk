# Section 4.2 / ref. [18]: moving-load receptances of the periodically supported rail, per speed.
# Each table's folder is named by its content (track, track numerics, wheel offsets: common.smk TABLES,
# docs/workflow.md), so {track} is that key, not a scenario's name.


rule receptance:
    """Receptance matrices a_{p-k}(k Omega_0, d) for one track, wheel set and speed (rail.moving)."""
    output:
        "results/receptance/{track}/V{speed}.nc",
    wildcard_constraints:
        speed="[^_/]+",
    priority: table_priority
    params:
        code=code("receptance.py"),
        cfg=table_config,
        offsets=table_offsets,
        speed=table_speed,
        bays=table_bays,
    message:
        "receptance table {output}: V = {wildcards.speed} m/s, offsets {params.offsets} m"
    log:
        "logs/receptance/{track}/V{speed}.log",
    benchmark:
        "benchmarks/receptance/{track}/V{speed}.tsv"
    resources:
        mem_mb=1200,
        runtime=10,
    script:
        "../scripts/receptance.py"


rule receptance_bloch:
    """Receptance tables a_{p-k}((k + r/N) Omega_0, d), r = 0..N/2, for a roughness periodic over N
    bays (rail.moving.bloch_tables)."""
    output:
        "results/receptance/{track}/V{speed}_N{bays}.nc",
    wildcard_constraints:
        speed="[^_/]+",
        bays="[0-9]+",
    params:
        code=code("receptance.py"),
        cfg=table_config,
        offsets=table_offsets,
        speed=table_speed,
        bays=table_bays,
    message:
        "receptance tables {output}: V = {wildcards.speed} m/s, N = {wildcards.bays} bays, offsets {params.offsets} m"
    log:
        "logs/receptance/{track}/V{speed}_N{bays}.log",
    benchmark:
        "benchmarks/receptance/{track}/V{speed}_N{bays}.tsv"
    resources:
        mem_mb=2200,
        runtime=30,
    script:
        "../scripts/receptance.py"


rule receptances:
    """Named target: the receptance tables of the default scenario at every configured speed."""
    input:
        PLAN.receptance_tables(),
