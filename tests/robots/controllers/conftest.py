"""Fixtures of the controller tests."""

import jax
import pytest

from ekm.data import load_default_map


@pytest.fixture(scope="module")
def signed_map():
    """Trial 0 of the shipped signed-chart map: ``(ekm, cfg)``."""
    saved = load_default_map("signed")
    return jax.tree.map(lambda a: a[0], saved.ekm), saved.cfg
