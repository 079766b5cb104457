"""sm_dance_bot: SMACC2's reference navigation machine (smacc2_sm_reference_library/sm_dance_bot) on
smacc_py, in turtlebot3_world against sim2d and the Nav2-style stack.

MsDanceBotRunMode [StAcquireSensors → StEventCountDown → StNavigateToWaypointsX → SsRadialPattern1..3,
SsFPattern1, SsSPattern1 and the top-level rotations and straight motions between them →
StNavigateToWaypoint1] → StFinalState; an over-temperature switches to MsDanceBotRecoveryMode, which
resumes the run mode where it was left (deep history). Orthogonals: navigation (cl_nav2z), obstacle
perception (lidar), LED (a service client), temperature sensor, string publisher, service3, timer and an
updatable publisher.

Modules: ``clients`` (the machine's own clients and behaviors), ``orthogonals``, ``modestates`` (mode
states, EvGlobalError, loop counting), ``st_navigation`` and ``st_motions`` (top-level states),
``ss_radial``, ``ss_f_pattern``, ``ss_s_pattern`` (superstates and their inner states, declared with
``loop_pattern``, the loop skeleton they share), ``waypoints``
(the geometry, and every change from upstream's with its reason), ``support_nodes`` (the LED, service3
and temperature nodes of upstream's launch file) and ``demo`` (the whole run).

Run: ``smacc-run sm_dance_bot --ros-args -p use_sim_time:=true`` against a running stack and
``python -m smacc_py.state_machines.sm_dance_bot.support_nodes``, or everything with
``python -m smacc_py.state_machines.sm_dance_bot.demo --rtf max``.
"""

from smacc_py.state_machines.sm_dance_bot.modestates import (
    LOOPS_KEY,
    RECOVERIES_KEY,
    EvGlobalError,
    MsDanceBotRecoveryMode,
    MsDanceBotRunMode,
    StFinalState,
)
from smacc_py.state_machines.sm_dance_bot.sm_dance_bot import SmDanceBot
from smacc_py.state_machines.sm_dance_bot.ss_f_pattern import SsFPattern1
from smacc_py.state_machines.sm_dance_bot.ss_radial import (
    SsRadialPattern1,
    SsRadialPattern2,
    SsRadialPattern3,
)
from smacc_py.state_machines.sm_dance_bot.ss_s_pattern import SsSPattern1
from smacc_py.state_machines.sm_dance_bot.st_motions import StNavigateForward1
from smacc_py.state_machines.sm_dance_bot.st_navigation import StAcquireSensors, StNavigateToWaypointsX

STATE_MACHINE = SmDanceBot

#: Superstates with an inner loop, and how many iterations each runs.
LOOPING_SUPERSTATES = (SsRadialPattern1, SsRadialPattern2, SsRadialPattern3, SsFPattern1, SsSPattern1)

__all__ = [
    "LOOPING_SUPERSTATES",
    "LOOPS_KEY",
    "RECOVERIES_KEY",
    "STATE_MACHINE",
    "EvGlobalError",
    "MsDanceBotRecoveryMode",
    "MsDanceBotRunMode",
    "SmDanceBot",
    "SsFPattern1",
    "SsRadialPattern1",
    "SsRadialPattern2",
    "SsRadialPattern3",
    "SsSPattern1",
    "StAcquireSensors",
    "StFinalState",
    "StNavigateForward1",
    "StNavigateToWaypointsX",
]
