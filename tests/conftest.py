"""Shared fixtures: the report's rail steel and the repository paths."""

from pathlib import Path

import pytest

from rail import halfspace

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
