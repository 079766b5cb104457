"""AMCL update time on the TB3 world map: laser (likelihood field) weighting and a full filter update.

Target (brief): ≤ 3 ms median for an AMCL update at 2000 particles × 60 beams. "laser" is the
sensor model alone (endpoints for all particles, field lookup, Σ log pz); "full update" is what one
scan costs when the filter updates: motion model + laser + tempered re-weighting (ESS bisection) +
KLD low-variance resampling (the count pinned by min_particles = max_particles). "estimate" is the
heaviest-cluster pose for amcl_pose.

"laser models" compares, at 2000 particles on the same scan and cloud, the laser update and the full
update of likelihood_field, likelihood_field_prob without beam skipping and with it (do_beamskip on
a converged cloud), and prints each median's ratio to likelihood_field's.

Run: ``.venv/bin/python -m bench.bench_amcl`` (``--no-record`` to only print; ``--model
likelihood_field_prob`` or ``beam`` for the per-particle-count rows, likelihood_field by default).
"""

from __future__ import annotations

import argparse
from dataclasses import replace
from functools import partial
from pathlib import Path

import numpy as np

from bench.harness import Benchmark
from nav_stack.core.costmap.observation import LaserScan
from nav_stack.core.grid import GridSpec
from nav_stack.core.localization import Amcl, AmclParams
from nav_stack.core.localization.likelihood_field_prob import LikelihoodFieldProbModel
from nav_stack.core.localization.params import LASER_MODELS, LIKELIHOOD_FIELD, LIKELIHOOD_FIELD_PROB
from nav_stack.core.localization.sensor_model import Beams, select_beams
from nav_stack.core.map_io import load_map
from navsuite_testing.nav.fake_lidar import fake_scan

MAP = Path(__file__).resolve().parents[1] / "maps" / "turtlebot3_world.yaml"


def parse_cli() -> argparse.Namespace:
    """``--no-record`` (bench.harness's) and ``--model``: the laser model of the per-count rows."""
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--no-record", action="store_true",
                        help="print only; do not append to bench/history.jsonl")
    parser.add_argument("--model", choices=LASER_MODELS, default=LIKELIHOOD_FIELD,
                        help="laser_model_type of the per-particle-count rows (default: %(default)s)")
    return parser.parse_args()


def main() -> None:
    model = parse_cli().model
    bench = Benchmark("amcl")
    occupancy = load_map(MAP)
    pose = (-2.0, -0.5, 0.0)
    scan = fake_scan(occupancy.data, occupancy.spec, pose, noise_std=0.01, rng=np.random.default_rng(0))
    suffix = "" if model == LIKELIHOOD_FIELD else f", {model}"
    for n in (500, 2000, 5000):
        params = AmclParams(min_particles=n, max_particles=n, laser_model_type=model)
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
            f"laser update, {n} particles, {beams.ranges.size} beams{suffix}",
            laser,
            "ms",
            1e3,
            note=f"{model.replace('_', ' ')}, TB3 map",
        )
        def full_update(a: Amcl = amcl, odom: list[float] = [0.0]) -> None:  # noqa: B006 - call counter
            odom[0] = 0.3 - odom[0]  # alternate 0 ↔ 0.3 m so every call passes update_min_d
            a.update((odom[0], 0.0, 0.0), scan)

        full = bench.time(f"full update {n} particles", full_update, repeat=100, warmup=5)
        bench.record(f"full update (motion+laser+resample), {n} particles{suffix}", full, "ms", 1e3)
        est = bench.time(f"estimate {n} particles", amcl.estimate, repeat=100, warmup=5)
        bench.record(f"pose estimate (clusters), {n} particles{suffix}", est, "ms", 1e3)
    laser_models(bench, occupancy.data, occupancy.spec, scan, pose)
    building_sized(bench)
    bench.save()


def _laser_update(amcl: Amcl, beams: Beams) -> None:
    """One laser weighting of the cloud; likelihood_field_prob as on a converged filter (skips if asked)."""
    if isinstance(amcl.model, LikelihoodFieldProbModel):
        amcl.model.weigh(amcl.particles, beams, converged=True)
    else:
        amcl.model.log_likelihood(amcl.particles, beams)


def laser_models(bench: Benchmark, occupancy: np.ndarray, spec: GridSpec, scan: LaserScan,
                 pose: tuple[float, float, float]) -> None:
    """likelihood_field vs likelihood_field_prob (without and with beam skipping), same scan and cloud."""
    base = AmclParams(min_particles=2000, max_particles=2000)
    variants = {
        LIKELIHOOD_FIELD: base,
        LIKELIHOOD_FIELD_PROB: replace(base, laser_model_type=LIKELIHOOD_FIELD_PROB),
        f"{LIKELIHOOD_FIELD_PROB} + beam skipping": replace(base, laser_model_type=LIKELIHOOD_FIELD_PROB,
                                                            do_beamskip=True),
    }
    medians: dict[str, tuple[float, float]] = {}
    for label, params in variants.items():
        amcl = Amcl(params, occupancy, spec, np.random.default_rng(1))
        amcl.set_initial_pose(*pose, np.diag([0.01, 0.01, 0.005]))  # σ 0.1 m: converged after 1 resample
        beams = select_beams(scan, (0.0, 0.0, 0.0), params)
        laser = bench.time(f"laser update 2000 particles, {label}",
                           partial(_laser_update, amcl, beams), repeat=200, warmup=10)

        def full_update(a: Amcl = amcl, odom: list[float] = [0.0]) -> None:  # noqa: B006 - call counter
            odom[0] = 0.3 - odom[0]
            a.update((odom[0], 0.0, 0.0), scan)

        full = bench.time(f"full update 2000 particles, {label}", full_update, repeat=100, warmup=5)
        skipping = amcl.last_scan_weights is not None and amcl.last_scan_weights.skipping
        note = f"{beams.ranges.size} beams" + (", skipping ran" if skipping else "")
        for what, stats in (("laser update", laser), ("full update", full)):
            bench.record(f"laser model compare: {what}, 2000 particles, {label}", stats, "ms", 1e3, note=note)
        medians[label] = (laser.median, full.median)
    ref_laser, ref_full = medians[LIKELIHOOD_FIELD]
    for label, (laser_s, full_s) in medians.items():
        print(f"amcl: {label}: laser {laser_s * 1e3:.3f} ms ({laser_s / ref_laser:.2f}x likelihood_field), "
              f"full update {full_s * 1e3:.3f} ms ({full_s / ref_full:.2f}x)", flush=True)


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
