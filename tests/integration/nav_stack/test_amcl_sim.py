"""amcl on a scripted tour of turtlebot3_world in sim2d (drifting odometry): tracking, global, kidnap.

Each test prints its measured numbers (run with -s to see them); bench/bench_localization.py records
them. Odometry noise alphas are 0.05 instead of Nav2's 0.2 (sim2d's drift is far smaller than 0.2
implies; with 0.2 the filter's own motion noise dominates). The asserted bounds (0.25 m / 0.20 rad RMS)
are looser than the targets (0.05 m / 0.05 rad): they catch a lost or biased filter, not tuning.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("nav2_msgs.srv")

from tests.helpers.nav_ros_loc_tour import CONVERGED, TourRun

pytestmark = [pytest.mark.ros, pytest.mark.slow]
TUNING = {"alpha1": 0.05, "alpha2": 0.05, "alpha3": 0.05, "alpha4": 0.05}


def _check_run(result: Any) -> None:
    assert result.finished, result.log[-2000:]
    assert result.collisions == 0
    assert len(result.samples) > 30


def test_tracking_from_the_seed_initial_pose(ros_context: Any, tmp_path: Path) -> None:
    result = TourRun(ros_context, rtf=4.0, amcl_params=TUNING).run(tmp_path)
    _check_run(result)
    rms_xy, rms_yaw = result.rms_after(0)  # the start pose is known: every pose counts
    worst = max(s.error_xy for s in result.samples)
    print(f"\ntracking: {len(result.samples)} poses, RMS {rms_xy:.3f} m / {rms_yaw:.3f} rad, "
          f"max {worst:.3f} m")
    assert rms_xy < 0.25 and rms_yaw < 0.20


CORE_GAP = ("nav_stack.core.localization with the cube-sum likelihood field does not converge on this tour "
            "yet (bench/RESULTS.md, localization rows); the node side is exercised by test_amcl.py")


@pytest.mark.xfail(reason=CORE_GAP, strict=False)
def test_global_localization_converges_on_the_tour(ros_context: Any, tmp_path: Path) -> None:
    result = TourRun(ros_context, rtf=4.0, global_localization=True, amcl_params=TUNING).run(tmp_path)
    _check_run(result)
    start = result.converged_index()
    assert start is not None and len(result.samples) - start >= 10, \
        [round(s.error_xy, 2) for s in result.samples]
    print(f"\nglobal: converged (< {CONVERGED} m) after {result.samples[start].distance:.2f} m driven, "
          f"RMS afterwards {result.rms_after(start)[0]:.3f} m")


@pytest.mark.xfail(reason=CORE_GAP, strict=False)
def test_kidnapped_robot_is_recovered(ros_context: Any, tmp_path: Path) -> None:
    params = {**TUNING, "recovery_alpha_slow": 0.001, "recovery_alpha_fast": 0.1}
    result = TourRun(ros_context, rtf=4.0, kidnap=True, amcl_params=params).run(tmp_path)
    _check_run(result)
    assert result.kidnap_time is not None
    before = result.converged_index(until=result.kidnap_time)
    assert before is not None, "not localized before the kidnapping"
    after = result.converged_index(after=result.kidnap_time)
    assert after is not None and len(result.samples) - after >= 5, \
        [(round(s.t, 1), round(s.error_xy, 2)) for s in result.samples]
    recovery = result.samples[after].t - result.kidnap_time
    print(f"\nkidnap: recovered {recovery:.1f} sim s after a 2 m teleport")
