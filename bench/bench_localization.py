"""Localization quality of the amcl node against sim2d ground truth on the scripted turtlebot3_world tour.

Three runs (navsuite_testing/localization/tour.py: sim2d with drifting odometry, in lockstep at --rtf max,
map_server + amcl + lifecycle_manager_localization as child processes, ground-truth waypoint driver):
  tracking  from the seed's initial pose (-2.0, -0.5, 0): RMS position / yaw error of every amcl_pose;
  global    reinitialize_global_localization, no initial pose: distance driven until the error stays
            below 0.25 m (-1 when it never does);
  kidnap    a 2 m teleport with recovery_alpha_slow/fast 0.001/0.1: sim seconds until the error stays
            below 0.25 m again, from the true pose or its 180° twin (the world is symmetric but for
            one block: TWIN_NOTE in the helper); -1 when it never does.
Nav2's default parameters (alphas 0.2, sigma_hit 0.2, 60 beams, 500–2000 particles) plus min_ess_ratio
0.5; the kidnap run enables recovery (0.001 / 0.1).

Run: ``.venv/bin/python -m bench.bench_localization`` (``--no-record`` to only print).
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")

import rclpy
from rclpy.context import Context

from bench.harness import Benchmark, parse_cli
from navsuite_testing.localization.tour import CONVERGED, RECOVERY, TourResult, TourRun


def _run(**kwargs: object) -> TourResult:
    context = Context()
    rclpy.init(context=context)
    try:
        with tempfile.TemporaryDirectory() as directory:
            return TourRun(context, **kwargs).run(Path(directory))  # type: ignore[arg-type]
    finally:
        rclpy.try_shutdown(context=context)


def main() -> None:
    parse_cli(__doc__)
    bench = Benchmark("localization")
    note = "sim2d drift, lockstep rtf max, Nav2 defaults, product likelihood, min_ess_ratio 0.5"

    tracking = _run()
    rms_xy, rms_yaw = tracking.rms_after(0)
    poses = len(tracking.samples)
    bench.record_value("tracking RMS position error", rms_xy, "m", note=f"{poses} poses, {note}")
    bench.record_value("tracking RMS yaw error", rms_yaw, "rad", note=note)
    worst = max(s.error_xy for s in tracking.samples)
    bench.record_value("tracking max position error", worst, "m", note=note)

    global_run = _run(global_localization=True)
    start = global_run.converged_index()
    distance = global_run.samples[start].distance if start is not None else -1.0
    bench.record_value("global localization: distance to converge (< 0.25 m)", distance, "m",
                       note=("-1 = not converged on the tour; " if start is None else "") + note)

    kidnap = _run(amcl_params=RECOVERY, kidnap=True)
    after = kidnap.converged_index(after=kidnap.kidnap_time or 0.0, up_to_symmetry=True)
    recovery = kidnap.samples[after].t - (kidnap.kidnap_time or 0.0) if after is not None else -1.0
    twin = after is not None and kidnap.samples[-1].error_xy >= CONVERGED
    outcome = "-1 = not recovered; " if after is None else "on the 180° twin; " if twin else ""
    bench.record_value("kidnap (2 m teleport) recovery time", recovery, "sim s", note=outcome + note)
    bench.save()


if __name__ == "__main__":
    main()
