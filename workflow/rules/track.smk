# Section 4.2 / ref. [18]: moving-load receptances of the periodically supported rail, per speed.


rule receptance:
    """Receptance matrices a_{p-k}(k Omega_0, d) for one track and speed (rail.moving)."""
    output:
        "results/receptance/{track}/V{speed}.nc",
    params:
        code=code("receptance.py"),
        cfg=track_config,
        offsets=wheel_offsets,
    message:
        "receptance table: track {wildcards.track}, V = {wildcards.speed} m/s, offsets {params.offsets} m"
    log:
        "logs/receptance/{track}/V{speed}.log",
    benchmark:
        "benchmarks/receptance/{track}/V{speed}.tsv"
    resources:
        mem_mb=2000,
        runtime=10,
    script:
        "../scripts/receptance.py"


rule receptances:
    """Named target: the receptance tables of the default track at every configured speed."""
    input:
        receptance_tables(),
