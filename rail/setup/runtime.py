"""What the Snakefile settles before it reads a rule: the BLAS threads its jobs inherit, and whether
the run only writes the HTML report, and whether the files it must write fit the file-size limit.
Imports nothing heavy (no numpy): the Snakefile calls it first.
"""

from __future__ import annotations

__all__ = ["BLAS_THREAD_VARIABLES", "one_blas_thread", "reporting_only", "check_file_size_limit"]

# The thread-count variables of OpenBLAS, OpenMP and MKL.
BLAS_THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")


def one_blas_thread(environ) -> dict:
    """One BLAS/OpenMP thread per job, unless the caller's environment says otherwise.

    The parallelism is Snakemake's -j locally and cpus_per_task=1 on SLURM. With the libraries'
    default of one thread per core, two jobs on two cores run four busy-waiting threads, and a
    400-point Gauss rule costs 1.7 s CPU instead of 0.03 s. Jobs inherit the environment of the
    process that sets it, so the Snakefile calls this before its first include imports numpy.

    Parameters
    ----------
    environ : MutableMapping
        The environment to set (``os.environ``); a variable it holds already is kept.

    Returns
    -------
    dict
        The three variables and their values after the call.
    """
    for var in BLAS_THREAD_VARIABLES:
        environ.setdefault(var, "1")
    return {var: environ[var] for var in BLAS_THREAD_VARIABLES}


def reporting_only(argv) -> bool:
    """Whether ``snakemake --report report.html`` (without --report-after-run) runs: then the default
    target is report_all (the report of what is built) instead of all (the figure set).

    Parameters
    ----------
    argv : list of str
        The command line (``sys.argv``).

    Returns
    -------
    bool
    """
    return any(a == "--report" or a.startswith("--report=") for a in argv) and "--report-after-run" not in argv


def check_file_size_limit(root, limit: int | None = None) -> None:
    """Refuse, naming the file, a file-size limit (``ulimit -f``) below a workflow source file.

    Snakemake copies the Snakefile and every rule file it includes into its source cache (and each
    script it runs) before anything else; under a smaller limit that write fails with "[Errno 27] File
    too large" and names no file (issue 57). The limit is checked against the largest of them here,
    where the file can be named. Result files (several MB for a growth run) are written by
    rail.setup.io.write_netcdf, whose error names the file.

    Parameters
    ----------
    root : path
        The project folder (holding the Snakefile and workflow/).
    limit : int, optional
        The limit [bytes] (default: this process's soft RLIMIT_FSIZE; none where the platform has no
        such limit).

    Returns
    -------
    None

    Raises
    ------
    OSError
        errno EFBIG, naming the largest source file, its size and the limit.
    """
    import errno
    from pathlib import Path

    if limit is None:
        try:
            import resource
        except ImportError:  # no file-size limits on this platform
            return
        limit = resource.getrlimit(resource.RLIMIT_FSIZE)[0]
        if limit == resource.RLIM_INFINITY:
            return
    root = Path(root)
    files = [root / "Snakefile", *sorted((root / "workflow").glob("rules/*.smk")), *sorted((root / "workflow").glob("scripts/*.py"))]
    sizes = {f: f.stat().st_size for f in files if f.is_file()}
    if not sizes:
        return
    biggest = max(sizes, key=sizes.get)
    if sizes[biggest] > limit:
        raise OSError(errno.EFBIG, f"the file-size limit (ulimit -f) is {limit} bytes, below {biggest} ({sizes[biggest]} bytes), "
                                   "which Snakemake copies into its source cache before it runs, and below the results (a growth "
                                   "file is several MB): raise the limit (ulimit -f unlimited)")
