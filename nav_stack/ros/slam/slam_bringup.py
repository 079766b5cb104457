"""The processes ``nav-bringup --slam`` runs in place of map_server + amcl (Nav2's ``slam:=True`` bringup).

Nav2's bringup with ``slam:=True`` drops map_server, amcl and lifecycle_manager_localization and
starts slam_toolbox plus a map_saver server under ``lifecycle_manager_slam``. The same here:

  slam                     nav_stack.ros.slam.slam_node: publishes /map (growing, transient local) and
                           map → odom; parameters from the ``slam`` section of the params file.
  map_saver                nav_stack.ros.slam.map_saver: ``map_saver/save_map`` (what ``map_saver_cli`` and
                           ``nav-explore -f`` call) saves the live /map.
  lifecycle_manager_slam   configures and activates both; ready when it logs "Managed nodes are active".

The navigation half of the stack (planner, controller, behaviors, bt_navigator and
lifecycle_manager_navigation) is unchanged: the global costmap's static layer subscribes /map
(transient local) and re-sizes itself to every map the SLAM node publishes (LayeredCostmap.set_map).

What changes for clients: no ``amcl`` node and no ``/amcl_pose`` (slam_toolbox publishes none either),
so a client must not wait for AMCL (BasicNavigator.waitUntilNav2Active(localizer='amcl') would hang;
Nav2 users pass a different localizer). ``/initialpose`` is ignored: the SLAM map frame is fixed by
``map_start_pose`` ([-2.0, -0.5, 0.0] = turtlebot3_world's frame from the seeds' spawn).
"""

from __future__ import annotations

import sys
from collections.abc import Sequence
from pathlib import Path

from ros_tools.launch import ProcessSpec

SLAM_MANAGER = "lifecycle_manager_slam"
SLAM_NODES = ("slam", "map_saver")
MANAGER_READY = r"Managed nodes are active"


def slam_processes(params_file: str | Path | Sequence[str | Path], *, use_sim_time: bool = True,
                   extra_ros_args: Sequence[str] = (), python: str = sys.executable,
                   ready_timeout: float = 60.0) -> list[ProcessSpec]:
    """ProcessSpecs for SLAM mode, in start order; the caller starts them before the navigation servers.

    Args:
        params_file: Nav2-style parameter file with a ``slam`` section (config/nav2_params.yaml), or
            several (later ones override earlier ones).
        use_sim_time: put every node on /clock (sim2d); false for a real robot.
        extra_ros_args: more ``--ros-args`` items for every node (e.g. ``-p``, remaps, log levels).
        python: interpreter to run the modules with.
        ready_timeout: wall seconds the manager may take to bring both nodes up.
    """
    files = [params_file] if isinstance(params_file, str | Path) else list(params_file)
    common = [*[arg for f in files for arg in ("--params-file", str(f))],
              "-p", f"use_sim_time:={str(use_sim_time).lower()}",
              *extra_ros_args]
    # ``python -m nav_stack.ros.slam.map_saver`` is map_saver_cli; the server is that module's main().
    saver = "import sys; from nav_stack.ros.slam.map_saver import main; sys.exit(main())"
    # One BLAS thread: the pose-graph solve's matrices are small, and on a loaded 2-core machine
    # OpenBLAS's spinning worker threads made one loop closure's optimisation 6x slower (2.4 s instead
    # of 0.4 s for 1600 nodes and 60 loop edges), long enough to miss the bond heartbeat.
    nodes = [ProcessSpec("slam", [python, "-m", "nav_stack.ros.slam.slam_node", "--ros-args", *common],
                         env={"OPENBLAS_NUM_THREADS": "1"}),
             ProcessSpec("map_saver", [python, "-c", saver, "--ros-args", *common])]
    manager = ProcessSpec(
        SLAM_MANAGER,
        [python, "-m", "nav_stack.ros.lifecycle.lifecycle_manager", "--ros-args",
         "-r", f"__node:={SLAM_MANAGER}",
         *common, "-p", f"node_names:=[{','.join(SLAM_NODES)}]", "-p", "autostart:=true"],
        ready=MANAGER_READY,
        ready_timeout=ready_timeout,
    )
    return [*nodes, manager]
