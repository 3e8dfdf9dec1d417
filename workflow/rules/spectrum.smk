# The linearised growth-rate spectrum (rail/growth_spectrum/, docs/growth-spectrum.md): which
# wavelengths grow and how fast, per speed, from the smooth rail. Named target rate_spectrum (README).
# Its Bloch tables (the spectrum's N-bay period, the scenario's own wheels) are the content-named
# receptance tables of workflow/rules/track.smk (common.smk rate_spectrum_table).


rule rate_spectrum_speed:
    """Growth-rate spectrum of one scenario at one speed (about 30 s CPU at 187 lines with the report's contact, issue 33; tables apart)."""
    input:
        kernels=kernels("tangent"),
        table=rate_spectrum_table,
    output:
        "results/spectrum/{scenario}/V{speed}.nc",
    wildcard_constraints:
        speed="[^_/]+",
        scenario="[^/]+",
    params:
        code=code("rate_spectrum.py"),
        cfg=scenario_config,
        speed=target_speed,
    log:
        "logs/spectrum/{scenario}/V{speed}.log",
    benchmark:
        "benchmarks/spectrum/{scenario}/V{speed}.tsv"
    resources:
        mem_mb=lambda w: cell_memory_mb(PLAN.objects[w.scenario], 1400, 4.5),
        runtime=lambda w: int(20 + 3 * PLAN.cell_head_seconds(w.scenario) / 60),  # the cell head's table (docs/cluster.md)
    script:
        "../scripts/rate_spectrum.py"


rule rate_spectrum_map:
    """The spectra of a scenario over its speeds: dataset and speed x wavelength map (one speed: the line alone)."""
    priority: PRIORITY_KERNELS  # a short drawing or summing job: not queued behind long jobs (issue 57)
    localrule: True
    input:
        rate_spectrum_speeds,
    output:
        data="results/spectrum/{scenario}/rate_spectrum.nc",
        figure=report("results/spectrum/{scenario}/rate_spectrum.png", caption="../report/rate_spectrum.rst", category="Growth-rate spectrum",
                      subcategory="{scenario}"),
        summary=report("results/spectrum/{scenario}/summary.md", caption="../report/rate_spectrum.rst", category="Growth-rate spectrum",
                       subcategory="{scenario}"),
        csv=report("results/spectrum/{scenario}/rate_spectrum.csv", caption="../report/rate_spectrum.rst", category="Growth-rate spectrum",
                   subcategory="{scenario}"),
        frequency_map=report("results/spectrum/{scenario}/rate_map.png", caption="../report/rate_spectrum.rst", category="Growth-rate spectrum",
                             subcategory="{scenario}"),
    params:
        code=code("rate_spectrum_map.py"),
    resources:
        mem_mb=300,
        runtime=5,
    log:
        "logs/spectrum/{scenario}/map.log",
    benchmark:
        "benchmarks/spectrum/{scenario}/map.tsv"
    script:
        "../scripts/rate_spectrum_map.py"


rule settled_spectrum:
    """The expected rail roughness under the wheels' roughness (wheel_source, issue 58): the level each band settles to
    and the time from a ground rail to the limit, from the scenario's spectrum (which carries the source)."""
    priority: PRIORITY_KERNELS  # a short drawing job: not queued behind long jobs (issue 57)
    localrule: True
    input:
        "results/spectrum/{scenario}/rate_spectrum.nc",
    output:
        figure=report("results/spectrum/{scenario}/settled.png", caption="../report/settled_spectrum.rst", category="Wheels' roughness",
                      subcategory="{scenario}"),
        csv=report("results/spectrum/{scenario}/settled.csv", caption="../report/settled_spectrum.rst", category="Wheels' roughness",
                   subcategory="{scenario}"),
        summary=report("results/spectrum/{scenario}/settled.md", caption="../report/settled_spectrum.rst", category="Wheels' roughness",
                       subcategory="{scenario}"),
    params:
        code=code("settled_spectrum.py"),
    resources:
        mem_mb=300,
        runtime=5,
    log:
        "logs/spectrum/{scenario}/settled.log",
    benchmark:
        "benchmarks/spectrum/{scenario}/settled.tsv"
    script:
        "../scripts/settled_spectrum.py"


rule rate_spectrum:
    """Named target: the growth-rate spectrum of the default scenario over figures.rate_spectrum.speeds."""
    input:
        "results/spectrum/default/rate_spectrum.png",


rule rate_spectrum_sweep:
    """The spectra of a sweep study's points (each at its speed) on the study's grid."""
    priority: PRIORITY_KERNELS  # a short drawing or summing job: not queued behind long jobs (issue 57)
    localrule: True
    input:
        rate_spectrum_sweep_points,
    output:
        data="results/spectrum_sweeps/{study}.nc",
        figure=report("results/spectrum_sweeps/{study}.png", caption="../report/rate_spectrum_sweep.rst", category="Growth-rate spectrum"),
    params:
        code=code("rate_spectrum_sweep.py"),
        cfg={},  # drawn from the spectra alone, each of which records its configuration
        swept=sweep_keys,
        grid=sweep_values,
        indices=sweep_indices,
        units=sweep_units,
    resources:
        mem_mb=500,
        runtime=5,
    log:
        "logs/spectrum_sweeps/{study}.log",
    benchmark:
        "benchmarks/spectrum_sweeps/{study}.tsv"
    script:
        "../scripts/rate_spectrum_sweep.py"


rule rate_spectrum_sweeps:
    """Named target: the growth-rate spectrum over every sweep study whose swept keys change it
    (not those sweeping only roughness.*: the spectrum is about the smooth rail)."""
    input:
        PLAN.rate_spectrum_sweep_targets(),


rule speed_study:
    """The dynamic-creepage study over speed in one dataset, figure and table: per mechanism, track and speed
    the fastest line and its frequency, the line nearest the pinned-pinned frequency, and whether the
    growing band keeps its frequency or its wavelength (rail.studies.speed_study)."""
    priority: PRIORITY_KERNELS  # a short drawing or summing job: not queued behind long jobs (issue 57)
    localrule: True
    input:
        spectra=[f for files in PLAN.speed_study_spectra().values() for f in files],
    output:
        data="results/dynamic_creepage/speeds.nc",
        figure=report("results/dynamic_creepage/speeds.png", caption="../report/speed_study.rst", category="Dynamic creepage"),
        table=report("results/dynamic_creepage/speeds.md", caption="../report/speed_study.rst", category="Dynamic creepage"),
    params:
        code=code("speed_study.py"),
        cfg={n: SCENARIOS[n] for n in PLAN.speed_study_spectra()},
        spectra=PLAN.speed_study_spectra(),
    resources:
        mem_mb=400,
        runtime=5,
    log:
        "logs/dynamic_creepage/speeds.log",
    benchmark:
        "benchmarks/dynamic_creepage/speeds.tsv"
    script:
        "../scripts/speed_study.py"


# The studies of config/studies/<name>.yaml (issue 57, item 9): a named target each, what the file builds of each
# case (its growth-rate spectrum, its study_<case> outputs) and the study's summary: dynamic_creepage,
# dynamic_creepage_speeds with the speed study's summary, rail_flexibility (issue 43, docs/dynamic-creepage.md),
# short_wave (issue 31), closure_study (workflow/rules/closure.smk) and irregular_track (workflow/rules/irregular.smk).
# A study file that is not valid stops its own target alone.
for _study in sorted({*PLAN.studies, *PLAN.broken_studies}):

    rule:
        name:
            _study
        input:
            PLAN.study_file_input(_study),
