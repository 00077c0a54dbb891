"""The large route, the derivation's last, is bounded in time too: past it the model is refused."""

import pytest

import lagrangian as lg
from lagrangian.derive import euler_lagrange


def _chain(n: int) -> lg.System:
    coordinates = [f"q{i}" for i in range(n)]
    kinetic = " + ".join(f"(1 + sin(q{i})^2)*q{i}_dot^2/2" for i in range(n))
    potential = " + ".join(f"cos(q{i} - q{(i + 1) % n})" for i in range(n))
    return lg.System.from_energies(kinetic, potential, coordinates=coordinates)


def test_large_route_out_of_time_is_a_one_line_model_error(monkeypatch):
    monkeypatch.setattr(euler_lagrange, "LARGE_SECONDS", 1e-4)
    with pytest.raises(lg.ModelError, match=r"not derived within 0\.0001 s \(8 coordinates\)"):
        _chain(8).equations_of_motion()


@pytest.mark.slow
def test_large_route_within_its_time_derives():
    eom = _chain(8).equations_of_motion()
    assert eom.mass_matrix.shape == (8, 8)
