"""amcl on a scripted tour of turtlebot3_world in sim2d (drifting odometry): tracking, global, kidnap.

Nav2's default parameters throughout (alphas 0.2, sigma_hit 0.2, 60 beams, 500–2000 particles);
the kidnap run enables recovery with Nav2's suggested recovery_alpha_slow/fast 0.001/0.1. Each test
prints its measured numbers (run with -s); bench/bench_localization.py records them. The bounds are
what the filter meets on a loaded 2-core machine (measured in 8 runs: tracking RMS 0.039–0.043 m /
0.025–0.03 rad, max 0.09–0.11 m, once 0.077 m RMS with a 0.46 m excursion), so they catch a biased
or lost filter without being timing-sensitive.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("nav2_msgs.srv")

from tests.helpers.nav_ros_loc_tour import CONVERGED, RECOVERED_SAMPLES, RECOVERY, TourRun

pytestmark = [pytest.mark.ros, pytest.mark.slow]


def _check_run(result: Any) -> None:
    assert result.finished, result.log[-2000:]
    assert result.collisions == 0
    assert len(result.samples) > 30


def test_tracking_from_the_seed_initial_pose(ros_context: Any, tmp_path: Path) -> None:
    result = TourRun(ros_context).run(tmp_path)
    _check_run(result)
    rms_xy, rms_yaw = result.rms_after(0)  # the start pose is known: every pose counts
    worst = max(s.error_xy for s in result.samples)
    print(f"\ntracking: {len(result.samples)} poses, RMS {rms_xy:.3f} m / {rms_yaw:.3f} rad, "
          f"max {worst:.3f} m")
    assert rms_xy < 0.08 and rms_yaw < 0.08


def test_global_localization_converges_on_the_tour(ros_context: Any, tmp_path: Path) -> None:
    result = TourRun(ros_context, global_localization=True).run(tmp_path)
    _check_run(result)
    start = result.converged_index()
    assert start is not None and len(result.samples) - start >= 10, \
        [round(s.error_xy, 2) for s in result.samples]
    rms_xy, _ = result.rms_after(start)
    print(f"\nglobal: converged (< {CONVERGED} m) after {result.samples[start].distance:.2f} m driven, "
          f"RMS afterwards {rms_xy:.3f} m")
    assert rms_xy < 0.08


def test_kidnapped_robot_is_recovered(ros_context: Any, tmp_path: Path) -> None:
    result = TourRun(ros_context, kidnap=True, amcl_params=RECOVERY).run(tmp_path)
    _check_run(result)
    assert result.kidnap_time is not None
    before = result.converged_index(until=result.kidnap_time)
    assert before is not None, "not localized before the kidnapping"
    # The world is point-symmetric but for one block: the 180° twin of the true pose counts too.
    after = result.converged_index(after=result.kidnap_time, up_to_symmetry=True)
    assert after is not None and len(result.samples) - after >= RECOVERED_SAMPLES, \
        [(round(s.t, 1), round(s.error_xy, 2), round(s.error_twin, 2)) for s in result.samples]
    recovery = result.samples[after].t - result.kidnap_time
    pose = "the true pose" if result.samples[-1].error_xy < CONVERGED else "the 180° twin of the true pose"
    print(f"\nkidnap: recovered {recovery:.1f} sim s after a 2 m teleport, on {pose}")
