"""Makes pendulum.csv, the "measured" damped pendulum of the lab example (README, tutorial).

    python docs/lab/make_data.py

A pendulum filmed at 25 frames a second for 20 s, its angle tracked in each frame: here
made without lagrangian, by SciPy's solve_ivp of theta'' + gamma theta' + (g/l) sin(theta)
= 0 (l = 0.62 m, gamma = 0.08 1/s, g = 9.81 m/s^2, released from rest at 25 degrees),
with the tracker's noise (Gaussian, 0.3 degrees, seed 33) and two frames where it lost
the bob (empty cells).  Run once; the file is kept in the repository.
"""

from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

LENGTH, GAMMA, G, START = 0.62, 0.08, 9.81, np.radians(25.0)
FRAMES, NOISE_DEG, LOST = np.arange(0, 501) / 25.0, 0.3, (137, 138)


def main() -> None:
    run = solve_ivp(
        lambda t, y: [y[1], -GAMMA * y[1] - G / LENGTH * np.sin(y[0])],
        (0.0, FRAMES[-1]), [START, 0.0], t_eval=FRAMES, method="DOP853", rtol=1e-12,
        atol=1e-12,
    )  # fmt: skip
    angle = np.degrees(run.y[0]) + NOISE_DEG * np.random.default_rng(33).standard_normal(
        FRAMES.size
    )
    rows = ["t [s],theta [deg]"]
    for frame, (t, value) in enumerate(zip(FRAMES, angle, strict=True)):
        rows.append(f"{t:.2f}," + ("" if frame in LOST else f"{value:.2f}"))
    Path(__file__).with_name("pendulum.csv").write_text("\n".join(rows) + "\n")


if __name__ == "__main__":
    main()
