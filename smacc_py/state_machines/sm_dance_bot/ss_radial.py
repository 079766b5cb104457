"""The three radial-pattern superstates and their inner loop (SMACC2: superstates/ss_radial_pattern_1..3
and states/radial_motion_states/sti_radial_*.hpp).

Each ray: StiRadialLoopStart (EvLoopContinue / EvLoopEnd) → StiRadialRotate (absolute heading
``k · 360° / rays`` for the k-th ray, k from 1) → StiRadialEndPoint (forward one ray length, LED on) →
StiRadialReturn (undo the recorded path backwards, LED off) → StiRadialLoopStart. The superstate leaves on
``EvLoopEnd[StiRadialLoopStart]`` (ENDLOOP).

SMACC2 declares one set of inner states in the namespaces SS1, SS2 and SS3; state names here are flat, so
the inner states carry the superstate's number: ``StiRadialLoopStart1`` is ``SS1::StiRadialLoopStart``.
Where upstream goes after each pattern: radial 1 → StRotateDegrees1 (upstream's own commented-out
alternative; its live transition goes to StNavigateReverse1 like radial 2, which would leave
StRotateDegrees1, StNavigateForward1 and StRotateDegrees2 unreachable), radial 2 → StNavigateReverse1,
radial 3 → StRotateDegrees4. A failed return goes on to the next ray (upstream drives the ray again,
which loops for ever when the behavior server keeps refusing the motion). Rays and lengths are in
waypoints.py.
"""

from __future__ import annotations

import math
from typing import ClassVar

from smacc_py.clients.cl_nav2z import CbAbsoluteRotate, CbNavigateForward, CbUndoPathBackwards, CpOdomTracker
from smacc_py.core import SmaccState
from smacc_py.state_machines.sm_dance_bot import waypoints as wp
from smacc_py.state_machines.sm_dance_bot.clients import CbLEDOff, CbLEDOn
from smacc_py.state_machines.sm_dance_bot.loop_pattern import LoopPattern, loop_end
from smacc_py.state_machines.sm_dance_bot.modestates import LoopingSuperstate, MsDanceBotRunMode
from smacc_py.state_machines.sm_dance_bot.orthogonals import OrNavigation


class _RadialSuperstate(LoopingSuperstate):
    """A radial pattern: ``total_iterations`` rays of ``ray_length`` m around the entry point."""

    ray_length: ClassVar[float] = 1.0

    @classmethod
    def ray_angle_increment_degree(cls) -> float:
        """Degrees between rays (SMACC2's ray_angle_increment_degree())."""
        return 360.0 / cls.total_iterations


class SsRadialPattern1(_RadialSuperstate, parent=MsDanceBotRunMode):
    """Radial pattern 1 (upstream: 2 rays of 4 m)."""

    inner_initial_state = "StiRadialLoopStart1"
    total_iterations, ray_length = wp.RADIAL_1
    reactions = loop_end("StiRadialLoopStart1", "StRotateDegrees1")


class SsRadialPattern2(_RadialSuperstate, parent=MsDanceBotRunMode):
    """Radial pattern 2 (upstream: 4 rays of 5 m)."""

    inner_initial_state = "StiRadialLoopStart2"
    total_iterations, ray_length = wp.RADIAL_2
    reactions = loop_end("StiRadialLoopStart2", "StNavigateReverse1")


class SsRadialPattern3(_RadialSuperstate, parent=MsDanceBotRunMode):
    """Radial pattern 3 (upstream: 2 rays of 4 m)."""

    inner_initial_state = "StiRadialLoopStart3"
    total_iterations, ray_length = wp.RADIAL_3
    reactions = loop_end("StiRadialLoopStart3", "StRotateDegrees4")


class _RadialInner(SmaccState):
    superstate: ClassVar[type[_RadialSuperstate]]

    def ss(self) -> _RadialSuperstate:
        """The enclosing radial superstate (SMACC2's ``context<SS>()``)."""
        return self.context(self.superstate)


class _Rotate(_RadialInner):
    """Turn to the next ray's absolute heading, LED off."""

    def runtime_configure(self) -> None:
        ss = self.ss()
        degrees = ss.completed() * ss.ray_angle_increment_degree()
        self.get_client_behavior(OrNavigation, CbAbsoluteRotate).target_yaw = math.radians(degrees)


class _EndPoint(_RadialInner):
    """Drive out along the ray, LED on."""

    def runtime_configure(self) -> None:
        self.get_client_behavior(OrNavigation, CbNavigateForward).distance = self.ss().ray_length


class _Return(_RadialInner):
    """Undo the ray backwards, LED off."""

    def on_exit(self) -> None:
        self.requires_component(CpOdomTracker).clear_path()


def _radial_states(n: int, superstate: type[_RadialSuperstate]) -> tuple[type[SmaccState], ...]:
    """``StiRadialLoopStart<n>``, ``StiRadialRotate<n>``, ``StiRadialEndPoint<n>``, ``StiRadialReturn<n>``.

    The rotation's heading and the ray's length are set on entry (``runtime_configure``): they depend
    on the ray and on the superstate, so the declared 0.0 and 1.0 are placeholders.
    """
    start, rotate, end, back = (f"StiRadialLoopStart{n}", f"StiRadialRotate{n}", f"StiRadialEndPoint{n}",
                                f"StiRadialReturn{n}")
    pattern = LoopPattern(superstate, __name__)
    return (
        pattern.loop_start(start, rotate, "Start (or end) another ray."),
        pattern.motion(rotate, CbAbsoluteRotate, 0.0, led=CbLEDOff, following=end, on_failure=start,
                       base=_Rotate),
        pattern.motion(end, CbNavigateForward, 1.0, wp.FORWARD_SPEED, led=CbLEDOn, following=back,
                       base=_EndPoint),
        pattern.motion(back, CbUndoPathBackwards, led=CbLEDOff, following=start, base=_Return),
    )


(StiRadialLoopStart1, StiRadialRotate1, StiRadialEndPoint1,
 StiRadialReturn1) = _radial_states(1, SsRadialPattern1)
(StiRadialLoopStart2, StiRadialRotate2, StiRadialEndPoint2,
 StiRadialReturn2) = _radial_states(2, SsRadialPattern2)
(StiRadialLoopStart3, StiRadialRotate3, StiRadialEndPoint3,
 StiRadialReturn3) = _radial_states(3, SsRadialPattern3)
