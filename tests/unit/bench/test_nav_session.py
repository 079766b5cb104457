"""Goal sampling and the ideal speed of the whole-stack benchmarks."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from bench.nav_session import free_poses, ideal_speed
from nav_stack.core.map_io import load_map
from nav_stack.ros.bringup.robot_params import params_for_robot

REPO = Path(__file__).resolve().parents[3]


def test_ideal_speed_is_the_controllers_desired_linear_vel() -> None:
    assert ideal_speed(params_for_robot("waffle")) == pytest.approx(0.26)
    assert ideal_speed(params_for_robot("tb4")) == pytest.approx(0.30)


def test_ideal_speed_is_the_slowest_link_of_the_velocity_chain() -> None:
    """Nav2's own file: MPPI's vx_max and the velocity smoother allow 0.5 m/s, the waffle drives at 0.26."""
    jazzy = REPO / "config" / "jazzy" / "nav2_params.yaml"
    assert ideal_speed(jazzy) == pytest.approx(0.5)
    assert ideal_speed(jazzy, "waffle") == pytest.approx(0.26)
    assert ideal_speed(jazzy, "tb4") == pytest.approx(0.306)


def test_ideal_speed_names_the_file_without_it(tmp_path: Path) -> None:
    params = tmp_path / "params.yaml"
    params.write_text("controller_server:\n  ros__parameters:\n    FollowPath: {}\n")
    with pytest.raises(ValueError, match=r"params\.yaml"):
        ideal_speed(params)


def test_free_poses_keep_their_clearance_from_every_blocked_cell(tmp_path: Path) -> None:
    # 20 x 20 cells of 0.1 m, free, with one occupied cell in the middle (P2 PGM: 0 = occupied)
    shades = np.full((20, 20), 254, dtype=int)
    shades[10, 10] = 0
    (tmp_path / "m.pgm").write_text("P2\n20 20\n255\n" + "\n".join(" ".join(map(str, row)) for row in shades))
    (tmp_path / "m.yaml").write_text("image: m.pgm\nresolution: 0.1\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n"
                                     "occupied_thresh: 0.65\nfree_thresh: 0.196\n")
    occupancy = load_map(tmp_path / "m.yaml")
    (row, col), = np.argwhere(occupancy.data != 0)
    blocked = np.array(occupancy.spec.cell_to_world(col, row))
    poses = free_poses(tmp_path / "m.yaml", 0.35)
    distance = np.hypot(*(poses - blocked).T)
    assert distance.min() >= 0.35 - 1e-9
    assert len(poses) == 400 - 37  # the 37 cells (the blocked one included) closer than 3.5 cells
