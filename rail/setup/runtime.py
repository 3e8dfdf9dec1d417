"""What the Snakefile settles before it reads a rule: the BLAS threads its jobs inherit, and whether
the run only writes the HTML report. Imports nothing heavy (no numpy): the Snakefile calls it first.
"""

from __future__ import annotations

__all__ = ["BLAS_THREAD_VARIABLES", "one_blas_thread", "reporting_only"]

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
