"""The Nav2 parameter file ``nav-bringup --robot NAME`` uses when ``--params`` does not name one.

Why one file per robot shape: the footprint, the speed limits and the lidar's range are robot facts
that several nodes read (both costmaps, the controller, AMCL, SLAM), and Nav2 keeps them in the
parameter file. The TurtleBot3s share config/nav2_params.yaml (the waffle's robot_radius 0.22 m also
covers the smaller burger, as in Nav2's own TB3 bringup); the round TurtleBot4 has
config/nav2_params_tb4.yaml. The names are sim2d's models (sim2d.core.robot.ROBOTS), restated here
because nav_stack never imports sim2d; a test checks that both lists agree. The files are shipped
data (navsuite_data), so the defaults hold in a checkout and in an installed wheel alike.
"""

from __future__ import annotations

from pathlib import Path

from navsuite_data import config_path, data_dir

CONFIG = data_dir("config")
PARAMS_BY_ROBOT: dict[str, Path] = {
    "waffle": config_path("nav2_params.yaml"),
    "burger": config_path("nav2_params.yaml"),
    "tb4": config_path("nav2_params_tb4.yaml"),
}
ROBOTS = tuple(PARAMS_BY_ROBOT)


def params_for_robot(robot: str) -> Path:
    """The parameter file of ``robot`` (one of ROBOTS); a ValueError names the known ones."""
    if robot not in PARAMS_BY_ROBOT:
        raise ValueError(f"robot: unknown model {robot!r} (known: {', '.join(ROBOTS)})")
    return PARAMS_BY_ROBOT[robot]
