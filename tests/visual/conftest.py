"""Shared models, runs and pixel helpers of the picture tests.

Pictures are checked for content (see ``pictures.py``): the pixels of a
rendered figure at the places where the data say something must be.
"""

from __future__ import annotations

import pytest

import lagrangian as lg
from visual.pictures import PENDULUM_WITH_BOB


@pytest.fixture(scope="session")
def bob_pendulum() -> lg.System:
    return lg.loads(PENDULUM_WITH_BOB, source="pendulum.toml")


@pytest.fixture(scope="session")
def bob_run(bob_pendulum):
    """2 s of the pendulum, densely sampled (the reference for positions)."""
    return bob_pendulum.simulate(t_end=2.0, n_out=4001)
