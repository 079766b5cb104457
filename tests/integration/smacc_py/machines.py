"""Small machines that exercise one cl_nav2z / timer / keyboard behavior each on the ROS runtime."""

from __future__ import annotations

import math

from smacc_py.clients.cl_keyboard import CbDefaultKeyboardBehavior, ClKeyboard
from smacc_py.clients.cl_nav2z import (
    CbAbortNavigation,
    CbAbsoluteRotate,
    CbNavigateBackwards,
    CbNavigateForward,
    CbNavigateGlobalPosition,
    CbNavigateNextWaypoint,
    CbPureSpinning,
    CbRotate,
    CbSetInitialPose,
    CbUndoPathBackwards,
    CbWaitNav2Nodes,
    ClNav2Z,
    CpAmcl,
    CpGoalCheckerSwitcher,
    CpOdomTracker,
    CpPlannerSwitcher,
    CpPose,
    CpWaypointNavigator,
)
from smacc_py.clients.cl_ros2_timer import CbTimerCountdownLoop, CbTimerCountdownOnce, ClRos2Timer
from smacc_py.core import (
    ABORT,
    SUCCESS,
    EvActionAborted,
    EvActionCancelled,
    EvActionSucceeded,
    EvCbFailure,
    EvCbSuccess,
    EvCountdownEnd,
    EvTimer,
    EvWaypointFinal,
    Orthogonal,
    SmaccState,
    SmaccStateMachineBase,
    SrEventCountdown,
    Transition,
    key_press_event,
    waypoint_event,
)


class OrNav(Orthogonal):
    def on_initialize(self) -> None:
        client = self.create_client(ClNav2Z)
        client.create_component(CpPose, "base_link", "map")
        client.create_component(CpOdomTracker)
        client.create_component(CpAmcl)
        client.create_component(CpWaypointNavigator, [(1.0, 0.0, 0.0), (2.0, 0.5, 1.0)])


class OrTime(Orthogonal):
    def on_initialize(self) -> None:
        self.create_client(ClRos2Timer)


class OrKeys(Orthogonal):
    def on_initialize(self) -> None:
        self.create_client(ClKeyboard)


class _Sm(SmaccStateMachineBase):
    def on_initialize(self) -> None:
        self.create_orthogonal(OrNav)
        self.create_orthogonal(OrTime)
        self.create_orthogonal(OrKeys)


def _outcome_states(machine: type) -> tuple[type[SmaccState], type[SmaccState]]:
    done = type("StDone", (SmaccState,), {}, parent=machine)
    failed = type("StFailed", (SmaccState,), {}, parent=machine)
    return done, failed


# ------------------------------------------------------------------ CbPureSpinning
class SmSpin(_Sm):
    initial_state = "StSpin"


class StSpin(SmaccState, parent=SmSpin):
    reactions = [
        Transition(EvCbSuccess[CbPureSpinning, OrNav], "StDone", SUCCESS),
        Transition(EvCbFailure[CbPureSpinning, OrNav], "StFailed", ABORT),
    ]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNav, CbPureSpinning, math.pi / 2, 0.5, timeout_s=8.0)


_outcome_states(SmSpin)


# ------------------------------------------------------------------ CbPureSpinning cut short by a state exit
SPIN_INTERRUPT_S = 2.0  # sim s; the full turn would take more than 12 s at 0.5 rad/s


class SmSpinInterrupted(_Sm):
    initial_state = "StSpinLong"


class StSpinLong(SmaccState, parent=SmSpinInterrupted):
    reactions = [
        Transition(EvTimer[CbTimerCountdownOnce, OrTime], "StDone", SUCCESS),
        Transition(EvCbSuccess[CbPureSpinning, OrNav], "StFailed", ABORT),
        Transition(EvCbFailure[CbPureSpinning, OrNav], "StFailed", ABORT),
    ]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNav, CbPureSpinning, 2 * math.pi, 0.5, timeout_s=60.0)
        cls.configure_orthogonal(OrTime, CbTimerCountdownOnce, SPIN_INTERRUPT_S)


_outcome_states(SmSpinInterrupted)


# ------------------------------------------------------------------ planner / goal-checker selection
class OrSelectors(Orthogonal):
    def on_initialize(self) -> None:
        client = self.create_client(ClNav2Z)
        client.create_component(CpPlannerSwitcher)
        client.create_component(CpGoalCheckerSwitcher)


class SmSelectors(SmaccStateMachineBase):
    initial_state = "StIdle"

    def on_initialize(self) -> None:
        self.create_orthogonal(OrSelectors)


type("StIdle", (SmaccState,), {}, parent=SmSelectors)


# ------------------------------------------------------------------ CbWaitNav2Nodes timeout
class SmWaitNodes(_Sm):
    initial_state = "StWait"


class StWait(SmaccState, parent=SmWaitNodes):
    reactions = [
        Transition(EvCbSuccess[CbWaitNav2Nodes, OrNav], "StDone", SUCCESS),
        Transition(EvCbFailure[CbWaitNav2Nodes, OrNav], "StFailed", ABORT),
    ]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNav, CbWaitNav2Nodes, timeout_s=5.0)


_outcome_states(SmWaitNodes)


# ------------------------------------------------------------------ cancel on state exit
class SmCancelOnExit(_Sm):
    initial_state = "StNavigate"


class StNavigate(SmaccState, parent=SmCancelOnExit):
    reactions = [
        Transition(EvTimer[CbTimerCountdownOnce, OrTime], "StAfter", SUCCESS),
        Transition(EvActionSucceeded[ClNav2Z, OrNav], "StFailed", ABORT),
        Transition(EvActionAborted[ClNav2Z, OrNav], "StFailed", ABORT),
    ]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNav, CbNavigateGlobalPosition, 1.0, 0.0, 0.0)
        cls.configure_orthogonal(OrTime, CbTimerCountdownOnce, 3.0)


class StAfter(SmaccState, parent=SmCancelOnExit):
    # The abandoned goal's cancellation must not reach the next state.
    reactions = [Transition(EvActionCancelled[ClNav2Z, OrNav], "StFailed", ABORT)]


type("StFailed", (SmaccState,), {}, parent=SmCancelOnExit)


# ------------------------------------------------------------------ relative motions and abort
class SmMotions(_Sm):
    initial_state = "StForward"


def _chain(machine: type, steps: list[tuple[str, type, tuple]]) -> None:
    for i, (name, behavior, args) in enumerate(steps):
        target = steps[i + 1][0] if i + 1 < len(steps) else "StDone"

        def configure(cls: type, behavior: type = behavior, args: tuple = args) -> None:
            cls.configure_orthogonal(OrNav, behavior, *args)

        type(
            name,
            (SmaccState,),
            {
                "reactions": [
                    Transition(EvCbSuccess[behavior, OrNav], target, SUCCESS),
                    Transition(EvCbFailure[behavior, OrNav], "StFailed", ABORT),
                ],
                "static_configure": classmethod(configure),
            },
            parent=machine,
        )
    _outcome_states(machine)


_chain(
    SmMotions,
    [
        ("StForward", CbNavigateForward, (0.5,)),
        ("StBackwards", CbNavigateBackwards, (0.3,)),
        ("StRotate", CbRotate, (90.0,)),
        ("StAbsoluteRotate", CbAbsoluteRotate, (180.0,)),
        ("StAbort", CbAbortNavigation, ()),
    ],
)


# ------------------------------------------------------------------ CbSetInitialPose
class SmInitialPose(_Sm):
    initial_state = "StInitialPose"


_chain(SmInitialPose, [("StInitialPose", CbSetInitialPose, (-2.0, -0.5, 0.0))])


# ------------------------------------------------------------------ undo path (record while a goal holds)
class SmUndo(_Sm):
    initial_state = "StRecord"


class StRecord(SmaccState, parent=SmUndo):
    reactions = [Transition(key_press_event("U")[CbDefaultKeyboardBehavior, OrKeys], "StUndo", SUCCESS)]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNav, CbNavigateGlobalPosition, 5.0, 0.0, 0.0)
        cls.configure_orthogonal(OrKeys, CbDefaultKeyboardBehavior)


_chain(SmUndo, [("StUndo", CbUndoPathBackwards, ())])


# ------------------------------------------------------------------ waypoints
class SmWaypoints(_Sm):
    initial_state = "StNextWaypoint"


class StNextWaypoint(SmaccState, parent=SmWaypoints):
    reactions = [
        Transition(waypoint_event(0)[ClNav2Z, OrNav], "StNextWaypoint", SUCCESS),
        Transition(EvWaypointFinal[ClNav2Z, OrNav], "StDone", SUCCESS),
        Transition(EvCbFailure[CbNavigateNextWaypoint, OrNav], "StFailed", ABORT),
    ]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNav, CbNavigateNextWaypoint)


_outcome_states(SmWaypoints)


# ------------------------------------------------------------------ timer loop
class SmTimerLoop(_Sm):
    initial_state = "StTicking"


class StTicking(SmaccState, parent=SmTimerLoop):
    reactions = [Transition(EvCountdownEnd[SrEventCountdown, "StTicking"], "StDone", SUCCESS)]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrTime, CbTimerCountdownLoop, 2.0)
        cls.static_create_state_reactor(
            SrEventCountdown,
            EvCountdownEnd[SrEventCountdown, "StTicking"],
            [EvTimer[CbTimerCountdownLoop, OrTime]],
            3,
        )


type("StDone", (SmaccState,), {}, parent=SmTimerLoop)
