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
