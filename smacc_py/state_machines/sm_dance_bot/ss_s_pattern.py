"""The S-pattern superstate and its inner loop (SMACC2: superstates/ss_s_pattern_1.hpp and
states/s_pattern_states/sti_spattern_*.hpp).

One iteration, for direction RIGHT (upstream's), with absolute headings: StiSPatternLoopStart →
Rotate1 (0°) → Forward1 (pitch1) → Rotate2 (-90°) → Forward2 (pitch2) → Rotate3 (0°) → Forward3
(pitch1) → Rotate4 (+90°) → Forward4 (pitch2) → StiSPatternLoopStart: a square wave along +x. Rotations
keep the LED off, forward legs switch it on. Upstream, a failed leg goes back to the rotation before
it and a failed rotation to the leg before it (or itself): a leg the behavior server keeps refusing (an
obstacle within its look-ahead) loops for ever. Here every failure goes on to the next state (ABORT),
so a refused motion costs one leg of the wave, never the machine. After
the last iteration ``EvLoopEnd[StiSPatternLoopStart]`` leaves for StRotateDegrees6 (ENDLOOP; upstream goes
to StNavigateReverse3 directly, leaving StRotateDegrees6, whose own successor is StNavigateReverse3,
unreachable). Sizes are in waypoints.py.
"""

from __future__ import annotations

from typing import ClassVar

from smacc_py.clients.cl_nav2z import CbAbsoluteRotate
from smacc_py.core import SmaccState
from smacc_py.state_machines.sm_dance_bot import waypoints as wp
from smacc_py.state_machines.sm_dance_bot.clients import CbLEDOff, CbLEDOn
from smacc_py.state_machines.sm_dance_bot.loop_pattern import LoopPattern, loop_end
from smacc_py.state_machines.sm_dance_bot.modestates import LoopingSuperstate, MsDanceBotRunMode


class SsSPattern1(LoopingSuperstate, parent=MsDanceBotRunMode):
    """A square wave (upstream: 9 iterations, pitches 0.75 and 1.45 m)."""

    inner_initial_state = "StiSPatternLoopStart"
    reactions = loop_end("StiSPatternLoopStart", "StRotateDegrees6")
    total_iterations = wp.S_ITERATIONS
    pitch1_length: ClassVar[float] = wp.S_PITCH_1
    pitch2_length: ClassVar[float] = wp.S_PITCH_2


_S = LoopPattern(SsSPattern1, __name__)


def _rotate(index: int, degrees: float) -> type[SmaccState]:
    """``StiSPatternRotate<index>``: turn to ``degrees`` (absolute), then the leg of the same index."""
    return _S.motion(f"StiSPatternRotate{index}", CbAbsoluteRotate, degrees, led=CbLEDOff,
                     following=f"StiSPatternForward{index}",
                     doc=f"Turn to {degrees:+.0f}° (absolute), LED off.")


def _forward(index: int, length: float, following: str, doc: str = "") -> type[SmaccState]:
    """``StiSPatternForward<index>``: drive ``length`` m with the LED on, then ``following``."""
    return _S.forward(f"StiSPatternForward{index}", length, led=CbLEDOn, following=following,
                      doc=doc or f"Drive {length:g} m, LED on.")


StiSPatternLoopStart = _S.loop_start("StiSPatternLoopStart", "StiSPatternRotate1",
                                     "Another period of the wave, or the end.")
StiSPatternRotate1 = _rotate(1, 0.0)
StiSPatternForward1 = _forward(1, SsSPattern1.pitch1_length, "StiSPatternRotate2")
StiSPatternRotate2 = _rotate(2, -90.0)
StiSPatternForward2 = _forward(2, SsSPattern1.pitch2_length, "StiSPatternRotate3")
StiSPatternRotate3 = _rotate(3, 0.0)
StiSPatternForward3 = _forward(3, SsSPattern1.pitch1_length, "StiSPatternRotate4")
StiSPatternRotate4 = _rotate(4, 90.0)
StiSPatternForward4 = _forward(4, SsSPattern1.pitch2_length, "StiSPatternLoopStart",
                               "Drive pitch2 back up, LED on; then the next period.")
