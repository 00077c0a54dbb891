"""The closed-form solves of one- and two-coordinate systems (numpy backend)."""

from __future__ import annotations

import numpy as np
import pytest

from lagrangian.numeric.backends import numpy_backend


@pytest.mark.parametrize("n", [1, 2])
@pytest.mark.parametrize("batch", [(), (7,), (3, 4)])
def test_equals_linalg_solve(n, batch):
    rng = np.random.default_rng(n + len(batch))
    matrix = rng.uniform(-1, 1, (*batch, n, n)) + 3 * np.eye(n)
    rhs = rng.uniform(-1, 1, (*batch, n))
    got = numpy_backend().solve(matrix, rhs)
    expected = np.linalg.solve(matrix, rhs[..., None])[..., 0]
    assert got.shape == expected.shape
    np.testing.assert_allclose(got, expected, rtol=1e-13, atol=1e-15)


@pytest.mark.parametrize("batch", [(), (3,)])
@pytest.mark.parametrize("n", [1, 2])
def test_singular_raises_as_linalg_does(n, batch):
    matrix = np.zeros((*batch, n, n))
    with pytest.raises(np.linalg.LinAlgError):
        numpy_backend().solve(matrix, np.ones((*batch, n)))
