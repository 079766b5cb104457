"""The whole stack for SLAM system runs: sim2d, SLAM (or map_server + amcl), the Nav2 servers, nav-explore.

Shared by tests/system/test_slam_exploration.py and bench/bench_slam_system.py. Processes start
through ros_tools.launch.Launcher in nav-bringup's order. The stack is composed here from the
server modules (each ``--autostart``) and nav_stack.ros.slam.slam_bringup.slam_processes, the function
``nav-bringup --slam`` uses; once nav-bringup exists the navigation half could come from it.
Output lines are kept (``lines``) so a failing test can show them and a run can be parsed.
"""

from __future__ import annotations

import re
import subprocess
import sys
import threading
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from nav_stack.core.grid import GridSpec
from nav_stack.core.map_io import load_map
from nav_stack.ros.bringup.bringup_components import COMPONENT_READY, component_role
from navsuite_testing.ros import REPO
from navsuite_testing.slam.world import dilate
from ros_tools.launch import Launcher, ProcessSpec

PARAMS_FILE = REPO / "config" / "nav2_params.yaml"
REFERENCE_MAP = REPO / "maps" / "turtlebot3_world.yaml"
START = (-2.0, -0.5, 0.0)
#: node name -> its module
NAV_SERVERS = {"planner_server": "nav_stack.ros.planning.planner_server",
               "controller_server": "nav_stack.ros.control.controller_server",
               "behavior_server": "nav_stack.ros.behaviors.behavior_server",
               "bt_navigator": "nav_stack.ros.navigator.bt_navigator"}


def _py(module: str, *args: str) -> list[str]:
    return [sys.executable, "-m", module, *args]


def sim_spec(rtf: float | str, seed: int = 0, participants: Sequence[str] = ()) -> ProcessSpec:
    """sim2d at the seeds' spawn; with ``participants`` (lockstep roles) it waits for them to report
    before its first step and never runs ahead of any node that reports (see ros_tools.runtime)."""
    lockstep = ["--lockstep-participants", ",".join(participants)] if participants else []
    return ProcessSpec("sim2d", _py("sim2d.ros.cli", "--world", "turtlebot3_world", "--robot", "waffle",
                                    "--rtf", str(rtf), "--seed", str(seed), "--x", str(START[0]),
                                    "--y", str(START[1]), "--yaw", str(START[2]), *lockstep),
                       ready=r"sim2d: world")


def nav_specs() -> list[ProcessSpec]:
    """The navigation servers on sim time, each bringing itself up (lifecycle_manager_navigation's job)."""
    ros = ["--ros-args", "--params-file", str(PARAMS_FILE), "-p", "use_sim_time:=true"]
    return [ProcessSpec(name, _py(module, "--autostart", *ros)) for name, module in NAV_SERVERS.items()]


def saved_map_specs(map_yaml: Path) -> list[ProcessSpec]:
    """Navigation on a saved map as ``nav-bringup --map`` runs it: the seeds' initial pose publisher,
    then every Nav2 node (map_server and amcl included) in one process, lockstep role ``nav2``.

    Why one process: AMCL's map -> odom must reach the controller before a goal. Across processes
    that waits on DDS discovery (seen with both cores loaded: a goal failed with TF_ERROR "frame
    [map] does not exist" in controller_server while the test's own listener had the frame); in one
    process the controller's listener shares AMCL's participant and has it at once.
    """
    return [
        ProcessSpec("initial_pose", _py("nav_stack.ros.localization.initial_pose_publisher", "--ros-args",
                                        "-p", "use_sim_time:=true", "-p", f"x:={START[0]}",
                                        "-p", f"y:={START[1]}", "-p", f"yaw:={START[2]}"), required=False),
        ProcessSpec(component_role("all"), _py("nav_stack.ros.bringup.nav_bringup", "component", "all",
                                               "--params", str(PARAMS_FILE), "--map", str(map_yaml)),
                    ready=COMPONENT_READY.format(name="all")),
    ]


class Stack:
    """A running launch; ``close()`` in ``finally``. ``lines`` holds every output line so far."""

    def __init__(self, specs: Sequence[ProcessSpec]) -> None:
        self.lines: list[str] = []
        self._lock = threading.Lock()
        self.launcher = Launcher(output=self._keep, color=False)
        self.launcher.start(specs)

    def _keep(self, line: str) -> None:
        with self._lock:
            self.lines.append(line)

    def alive(self) -> bool:
        """No required process has exited (the initial pose publisher exits once AMCL confirms)."""
        return all(r.proc.poll() is None for r in self.launcher.running if r.spec.required)

    def tail(self, n: int = 80) -> str:
        with self._lock:
            return "\n".join(self.lines[-n:])

    def close(self) -> None:
        self.launcher.shutdown()


def explore(map_file: Path, max_time: float, timeout: float) -> subprocess.CompletedProcess[str]:
    """Run ``nav-explore -f map_file`` to the end (its own process, the test's ROS environment).

    After ``timeout`` wall s it is killed and returns code -9 with what it printed so far, so that a
    stuck run fails with the explorer's goals in the message rather than at the test's time limit.
    """
    command = _py("nav_stack.ros.slam.explore", "-f", str(map_file), "--max-time", str(max_time))
    try:
        return subprocess.run(command, cwd=REPO, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired as expired:
        stdout, stderr = (out.decode(errors="replace") if isinstance(out, bytes) else out or ""
                          for out in (expired.stdout, expired.stderr))
        return subprocess.CompletedProcess(command, -9, stdout, f"{stderr}\nkilled after {timeout:.0f} s")


def _fields(pattern: str, line: str) -> tuple[str, ...]:
    """The groups ``pattern`` captures in ``line``; a ValueError naming both when it does not match."""
    match = re.search(pattern, line)
    if match is None:
        raise ValueError(f"no {pattern!r} in nav-explore's progress line {line!r}")
    return match.groups()


def progress_numbers(stdout: str) -> dict[str, float]:
    """Goals, reached, failed, mapped m² and sim s from nav-explore's last progress line."""
    line = [x for x in stdout.splitlines() if x.startswith("explore:") and "sim s" in x][-1]
    goals, reached, failed = (int(v) for v in _fields(r"goals (\d+) \(reached (\d+), failed (\d+)\)", line))
    mapped = float(_fields(r"mapped ([\d.]+) m2", line)[0])
    elapsed = float(_fields(r"\| ([\d.]+) sim s", line)[0])
    return {"goals": goals, "reached": reached, "failed": failed, "mapped": mapped, "sim_s": elapsed}


def observable_walls(reference: np.ndarray, spec: GridSpec, inside: tuple[float, float]) -> np.ndarray:
    """Occupied reference cells a lidar inside the arena can see: those 8-adjacent to free space
    connected to ``inside`` (the solid blocks' interiors and whatever lies behind the wall are not)."""
    free = reference == 0
    mx, my = (int(v) for v in spec.world_to_cell(*inside))
    reach = np.zeros_like(free)
    reach[my, mx] = True
    while True:  # flood fill by repeated dilation (the map is 384², a few hundred passes at most)
        grown = dilate(reach) & free
        if (grown == reach).all():
            break
        reach = grown
    return (reference >= 65) & dilate(reach)


def compare_with_reference(map_yaml: Path, reference: Path = REFERENCE_MAP,
                           inside: tuple[float, float] = START[:2]) -> float:
    """IoU (one-cell tolerance) of the map's occupied cells with the ``reference`` map's walls that a
    lidar can see from the free space around ``inside`` (m; the world's spawn). Both maps must share
    the map frame (SLAM's map_start_pose at the spawn, as nav-bringup --slam --world sets it)."""
    from navsuite_testing.slam.world import iou_dilated, resample_to

    ref = load_map(reference)
    est = load_map(map_yaml)
    truth = observable_walls(ref.data, ref.spec, inside)
    estimate = resample_to(est.data >= 65, est.spec, ref.spec, False)
    # Far outside the arena nothing is observable; an occupied estimate cell there is a plain error.
    return iou_dilated(estimate, truth)

