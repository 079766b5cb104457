"""AMCL update time on the TB3 world map: laser (likelihood field) weighting and a full filter update.

Target (brief): ≤ 3 ms median for an AMCL update at 2000 particles × 60 beams. "laser" is the
sensor model alone (endpoints for all particles, field lookup, Σ log pz); "full update" is what one
scan costs when the filter updates: motion model + laser + tempered re-weighting (ESS bisection) +
KLD low-variance resampling (the count pinned by min_particles = max_particles). "estimate" is the
heaviest-cluster pose for amcl_pose.

Run: ``.venv/bin/python -m bench.bench_amcl`` (``--no-record`` to only print).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from bench.harness import Benchmark
from nav_stack.core.localization import Amcl, AmclParams
from nav_stack.core.localization.sensor_model import select_beams
from nav_stack.core.map_io import load_map
from tests.helpers.nav_fake_lidar import fake_scan

MAP = Path(__file__).resolve().parents[1] / "maps" / "turtlebot3_world.yaml"


def main() -> None:
    bench = Benchmark("amcl")
    occupancy = load_map(MAP)
    pose = (-2.0, -0.5, 0.0)
    scan = fake_scan(occupancy.data, occupancy.spec, pose, noise_std=0.01, rng=np.random.default_rng(0))
    for n in (500, 2000, 5000):
        params = AmclParams(min_particles=n, max_particles=n)
        amcl = Amcl(params, occupancy.data, occupancy.spec, np.random.default_rng(1))
        amcl.set_initial_pose(*pose)
        beams = select_beams(scan, (0.0, 0.0, 0.0), params)
        laser = bench.time(
            f"laser update {n} particles",
            lambda a=amcl, b=beams: a.model.log_likelihood(a.particles, b),
            repeat=200,
            warmup=10,
        )
        bench.record(
            f"laser update, {n} particles, {beams.ranges.size} beams",
            laser,
            "ms",
            1e3,
            note="likelihood field, TB3 map",
        )
        def full_update(a: Amcl = amcl, odom: list[float] = [0.0]) -> None:  # noqa: B006 - call counter
            odom[0] = 0.3 - odom[0]  # alternate 0 ↔ 0.3 m so every call passes update_min_d
            a.update((odom[0], 0.0, 0.0), scan)

        full = bench.time(f"full update {n} particles", full_update, repeat=100, warmup=5)
        bench.record(f"full update (motion+laser+resample), {n} particles", full, "ms", 1e3)
        est = bench.time(f"estimate {n} particles", amcl.estimate, repeat=100, warmup=5)
        bench.record(f"pose estimate (clusters), {n} particles", est, "ms", 1e3)
    bench.save()


if __name__ == "__main__":
    main()
