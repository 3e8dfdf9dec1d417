"""Shared fixtures: the report's rail steel and the repository paths."""

import os

# One BLAS/OpenMP thread per test process unless the caller says otherwise, as the Snakefile does for
# jobs: with a worker per core (pytest-xdist), two-thread BLAS in each worker kept four threads
# busy-waiting on two cores (the test command took 496 s CPU against 297 s for the same tests in one
# process with one thread). Set before numpy is first imported here; xdist's workers inherit it.
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

from pathlib import Path  # noqa: E402

import pytest  # noqa: E402

from rail import halfspace  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="session")
def steel():
    """Rail steel of the report, section 3: E = 2.1e11 Pa, nu = 0.3, rho = 7850 kg/m^3."""
    return halfspace.ElasticMaterial(youngs_modulus=2.1e11, poisson_ratio=0.3, density=7850.0)


@pytest.fixture(scope="session")
def root():
    return ROOT


@pytest.fixture(scope="module")
def schema(root):
    """The configuration schema (config/schema/config.schema.yaml)."""
    from rail.setup.config import load_yaml

    return load_yaml(root / "config/schema/config.schema.yaml")


@pytest.fixture(scope="module")
def defaults(root):
    """The default configuration (config/config.yaml), as read from its file."""
    from rail.setup.config import load_yaml

    return load_yaml(root / "config/config.yaml")


@pytest.fixture(scope="module")
def default_study():
    """api.load('default'): the study of config/config.yaml."""
    from rail.app import api

    return api.load("default")


@pytest.fixture
def nothing_computed(monkeypatch):
    """Fail a test that computes (a receptance table, a fleet's tables, a growth run) before a door has
    checked its arguments."""
    from rail.app import api

    def never(*args, **kwargs):
        raise AssertionError("computed before the arguments were checked")

    monkeypatch.setattr(api.chain, "receptance_table", never)
    monkeypatch.setattr(api.chain, "fleet_tables", never)
    monkeypatch.setattr(api.chain, "grow", never)
