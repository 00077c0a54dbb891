"""SALI and GALI_k of given vectors (lagrangian.integrate.indicators), against their
definitions computed another way."""

from __future__ import annotations

import numpy as np

from lagrangian.integrate.indicators import gali, sali, starting_vectors


def test_sali_of_orthogonal_parallel_and_antiparallel_vectors():
    e1, e2 = np.eye(4)[:, 0], np.eye(4)[:, 1]
    vectors = np.stack([np.column_stack([e1, e1, e1]), np.column_stack([e2, e1, -e1])])
    assert np.allclose(sali(vectors), [np.sqrt(2.0), 0.0, 0.0])


def test_gali_is_the_volume_of_the_unit_vectors():
    rng = np.random.default_rng(3)
    w = rng.normal(size=(3, 4, 5))
    w /= np.linalg.norm(w, axis=1, keepdims=True)
    for k in (2, 3):
        # the volume: sqrt(det) of the Gram matrix of the k vectors, member by member
        gram = np.einsum("iam,jam->mij", w[:k], w[:k])
        assert np.allclose(gali(w, k), np.sqrt(np.linalg.det(gram)))
    # GALI_2 = |sin| of the angle between two unit vectors
    cosine = np.sum(w[0] * w[1], axis=0)
    assert np.allclose(gali(w, 2), np.sqrt(1 - cosine**2))


def test_the_starting_vectors_are_orthonormal_the_first_along_the_diagonal():
    vectors = starting_vectors(4, 3)
    assert np.allclose(vectors.T @ vectors, np.eye(3))
    assert np.allclose(vectors[:, 0], 0.5)
