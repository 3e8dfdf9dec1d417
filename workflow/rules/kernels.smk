# The compiled contact marches (numba): compiled once, before the jobs that roll the contact.


rule compile_kernels:
    """Compile the contact marches once (numba's cache, next to the sources), so that parallel jobs
    load them instead of each compiling them (about 30 s CPU per march in a fresh checkout)."""
    output:
        "results/cache/kernels_{which}.txt",
    wildcard_constraints:
        which="march|tangent",
    priority: PRIORITY_KERNELS
    params:
        code=code("compile_kernels.py"),
    log:
        "logs/kernels/{which}.log",
    benchmark:
        "benchmarks/kernels/{which}.tsv"
    resources:
        mem_mb=1100,
        runtime=10,
    script:
        "../scripts/compile_kernels.py"
