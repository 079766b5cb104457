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

from bench.harness import Benchmark, parse_cli
from nav_stack.core.localization import Amcl, AmclParams
from nav_stack.core.localization.sensor_model import select_beams
from nav_stack.core.map_io import load_map
from tests.helpers.nav_fake_lidar import fake_scan

MAP = Path(__file__).resolve().parents[1] / "maps" / "turtlebot3_world.yaml"


def main() -> None:
    parse_cli(__doc__)
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
    building_sized(bench)
    bench.save()


def building_sized(bench: Benchmark) -> None:
    """Issue 19: on a 2000 x 2000 map (100 m x 100 m), building the filter (its likelihood field) once,
    the field's memory, and a full update at 2000 particles, which must not grow with the map."""
    import time

    from bench.worlds import random_obstacle_costmap

    costs, spec = random_obstacle_costmap(2000, seed=2, n_obstacles=1600)
    occupancy = np.where(costs == 254, 100, 0).astype(np.int8)
    cells = np.argwhere(costs == 0)
    free = cells[np.argmin(np.hypot(cells[:, 0] - 1000, cells[:, 1] - 1000))]  # near the centre
    wx, wy = spec.cell_to_world(np.array([free[1]]), np.array([free[0]]))
    pose = (float(wx[0]), float(wy[0]), 0.0)
    scan = fake_scan(occupancy, spec, pose, noise_std=0.01, rng=np.random.default_rng(0))
    params = AmclParams(min_particles=2000, max_particles=2000)
    started = time.perf_counter()
    amcl = Amcl(params, occupancy, spec, np.random.default_rng(1))
    built_s = time.perf_counter() - started
    field_mb = sum(v.nbytes for v in vars(amcl.model.field).values() if isinstance(v, np.ndarray)) / 2**20
    bench.record_value("2000x2000 map: build the filter (likelihood field)", built_s * 1e3, "ms",
                       f"field arrays {field_mb:.0f} MiB")
    amcl.set_initial_pose(*pose)

    def full_update(odom: list[float] = [0.0]) -> None:  # noqa: B006 - call counter
        odom[0] = 0.3 - odom[0]
        amcl.update((odom[0], 0.0, 0.0), scan)

    full = bench.time("2000x2000 full update 2000 particles", full_update, repeat=50, warmup=3)
    bench.record("2000x2000 map: full update (motion+laser+resample), 2000 particles", full, "ms", 1e3,
                 note=f"likelihood field arrays {field_mb:.0f} MiB")


if __name__ == "__main__":
    main()
