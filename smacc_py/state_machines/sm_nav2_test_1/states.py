"""States of sm_nav2_test_1: the tutorial's reactions and tags, and the Jazzy package's retry count.

Beyond the tutorial (issue 45): a navigation goal whose navigator was lost (ClNav2Z's server watch: the
bt_navigator process died under the goal) goes to StRecoverNavigation<N>, which waits for Nav2's bonds
to heartbeat again (nav-bringup's respawn brings the stack back) and then drives to the same waypoint
again, at most MAX_NAVIGATION_RETRIES times per mission. Any other abort (no path, a controller
failure) still ends the mission on the tutorial's ABORT path.
"""

from __future__ import annotations

import logging
import math
from typing import TYPE_CHECKING

from smacc_py.clients.cl_keyboard import CbDefaultKeyboardBehavior
from smacc_py.clients.cl_nav2z import (
    CbNavigateGlobalPosition,
    CbPureSpinning,
    CbSetInitialPose,
    CbWaitNav2Nodes,
    ClNav2Z,
    is_server_lost,
)
from smacc_py.clients.cl_ros2_timer import CbTimerCountdownOnce
from smacc_py.core import (
    ABORT,
    SUCCESS,
    EvActionAborted,
    EvActionSucceeded,
    EvCbFailure,
    EvCbSuccess,
    EvTimer,
    SmaccEvent,
    SmaccState,
    Transition,
    key_press_event,
)
from smacc_py.state_machines.sm_nav2_test_1.orthogonals import OrKeyboard, OrNavigation, OrTimer

if TYPE_CHECKING:
    from smacc_py.state_machines.sm_nav2_test_1.sm_nav2_test_1 import SmNav2Test1

log = logging.getLogger("sm_nav2_test_1")

SENSORS_TIMEOUT_S = 15.0  # StAllSensorsGo's timer fallback (node clock)
ROTATE_YAW = math.pi  # StRotate: half a turn ...
ROTATE_MAX_W = 0.5  # ... at most 0.5 rad/s


class NAV2_READY(SUCCESS):  # noqa: N801  (SMACC2's tag name, shown in introspection)
    """Nav2's servers heartbeat their bonds."""


class NEXT(SUCCESS):
    """The operator pressed N."""


class NAVIGATOR_LOST(ABORT):  # noqa: N801  (a tag, named like SMACC2's)
    """The navigation server was lost under the goal: the mission retries once the stack is back."""


class EvMaxRetriesExceeded(SmaccEvent):
    """StSetInitialPose ran out of localization attempts, or StRecoverNavigation<N> of navigation retries."""


MAX_NAVIGATION_RETRIES = 2
NAVIGATION_RETRY_KEY = "navigation_retry_count"


def _config(state: SmaccState) -> SmNav2Test1:
    return state.sm  # type: ignore[return-value]


class StAllSensorsGo(SmaccState):
    """Wait for Nav2 (bonds), or 15 s, or key N."""

    reactions = [
        Transition(EvCbSuccess[CbWaitNav2Nodes, OrNavigation], "StSetInitialPose", NAV2_READY),
        Transition(EvTimer[CbTimerCountdownOnce, OrTimer], "StSetInitialPose", SUCCESS),
        Transition(key_press_event("N")[CbDefaultKeyboardBehavior, OrKeyboard], "StSetInitialPose", NEXT),
    ]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNavigation, CbWaitNav2Nodes)
        cls.configure_orthogonal(OrTimer, CbTimerCountdownOnce, SENSORS_TIMEOUT_S)
        cls.configure_orthogonal(OrKeyboard, CbDefaultKeyboardBehavior)


class StSetInitialPose(SmaccState):
    """Give AMCL the initial pose and wait for it to confirm (CbSetInitialPose); retry up to 3 times.

    As the tutorial states it: CbSetInitialPose(-2.0, -0.5, 0.0) on OrNavigation (the pose comes from
    the ``initial_pose`` parameter), EvCbSuccess → StNavigateToWaypoint1 (SUCCESS), EvCbFailure → this
    state again (ABORT). The tutorial's second EvCbFailure transition, to StFinalState, can never fire
    (the first match wins), so the attempts are counted as in the upstream package: the fifth entry
    posts EvMaxRetriesExceeded, which goes to StFinalState (ABORT).
    """

    MAX_RETRIES = 3
    MAX_ATTEMPTS = 1 + MAX_RETRIES
    ATTEMPT_COUNTER_KEY = "localization_attempt_count"

    reactions = [
        Transition(EvCbSuccess[CbSetInitialPose, OrNavigation], "StNavigateToWaypoint1", SUCCESS),
        Transition(EvCbFailure[CbSetInitialPose, OrNavigation], "StSetInitialPose", ABORT),
        Transition(EvMaxRetriesExceeded[CbSetInitialPose, OrNavigation], "StFinalState", ABORT),
    ]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNavigation, CbSetInitialPose, -2.0, -0.5, 0.0)
        cls.configure_orthogonal(OrKeyboard, CbDefaultKeyboardBehavior)

    def runtime_configure(self) -> None:
        attempts = self.get_global_sm_data(self.ATTEMPT_COUNTER_KEY, 0) + 1
        self.set_global_sm_data(self.ATTEMPT_COUNTER_KEY, attempts)
        behavior = self.get_client_behavior(OrNavigation, CbSetInitialPose)
        behavior.pose = _config(self).config.initial_pose
        if attempts > self.MAX_ATTEMPTS:
            self.post_event(
                EvMaxRetriesExceeded[CbSetInitialPose, OrNavigation](
                    reason=f"AMCL did not confirm the initial pose in {self.MAX_ATTEMPTS} attempts"
                )
            )
            return
        log.info("StSetInitialPose: attempt %d of %d, initial pose (%.2f, %.2f, %.2f)",
                 attempts, self.MAX_ATTEMPTS, *behavior.pose)

    def on_exit_SUCCESS(self) -> None:
        self.set_global_sm_data(self.ATTEMPT_COUNTER_KEY, 0)

    def on_exit_ABORT(self) -> None:
        attempts = self.get_global_sm_data(self.ATTEMPT_COUNTER_KEY, 0)
        if attempts > self.MAX_ATTEMPTS:
            log.error("StSetInitialPose: localization failed after %d attempts, aborting", self.MAX_ATTEMPTS)
        else:
            log.warning("StSetInitialPose: AMCL did not confirm the initial pose (attempt %d of %d)",
                        attempts, self.MAX_ATTEMPTS)


class StNavigateToWaypoint1(SmaccState):
    """Navigate to ``waypoint_1`` (default (2.0, 0.0, 0.0), the tutorial's)."""

    reactions = [
        Transition(EvActionSucceeded[ClNav2Z, OrNavigation], "StRotate", SUCCESS),
        Transition(EvActionAborted[ClNav2Z, OrNavigation], "StRecoverNavigation1", NAVIGATOR_LOST,
                   guard=is_server_lost),
        Transition(EvActionAborted[ClNav2Z, OrNavigation], "StFinalState", ABORT),
    ]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNavigation, CbNavigateGlobalPosition, 2.0, 0.0, 0.0)
        cls.configure_orthogonal(OrKeyboard, CbDefaultKeyboardBehavior)

    def runtime_configure(self) -> None:
        behavior = self.get_client_behavior(OrNavigation, CbNavigateGlobalPosition)
        behavior.set_goal(*_config(self).config.waypoint_1)


class StRotate(SmaccState):
    """Half a turn in place with CbPureSpinning(π, 0.5)."""

    reactions = [
        Transition(EvCbSuccess[CbPureSpinning, OrNavigation], "StNavigateToWaypoint2", SUCCESS),
        Transition(EvCbFailure[CbPureSpinning, OrNavigation], "StFinalState", ABORT),
    ]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNavigation, CbPureSpinning, ROTATE_YAW, ROTATE_MAX_W)
        cls.configure_orthogonal(OrKeyboard, CbDefaultKeyboardBehavior)


class StNavigateToWaypoint2(SmaccState):
    """Navigate to ``waypoint_2`` (see SmNav2Test1Params for why it is not upstream's (0, 0))."""

    reactions = [
        Transition(EvActionSucceeded[ClNav2Z, OrNavigation], "StFinalState", SUCCESS),
        Transition(EvActionAborted[ClNav2Z, OrNavigation], "StRecoverNavigation2", NAVIGATOR_LOST,
                   guard=is_server_lost),
        Transition(EvActionAborted[ClNav2Z, OrNavigation], "StFinalState", ABORT),
    ]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNavigation, CbNavigateGlobalPosition, 0.0, 0.0, 0.0)
        cls.configure_orthogonal(OrKeyboard, CbDefaultKeyboardBehavior)

    def runtime_configure(self) -> None:
        behavior = self.get_client_behavior(OrNavigation, CbNavigateGlobalPosition)
        behavior.set_goal(*_config(self).config.waypoint_2)


def _count_navigation_retry(state: SmaccState) -> None:
    """Count one more navigation retry; past MAX_NAVIGATION_RETRIES post EvMaxRetriesExceeded (ABORT)."""
    retries = state.get_global_sm_data(NAVIGATION_RETRY_KEY, 0) + 1
    state.set_global_sm_data(NAVIGATION_RETRY_KEY, retries)
    if retries > MAX_NAVIGATION_RETRIES:
        state.post_event(EvMaxRetriesExceeded[CbWaitNav2Nodes, OrNavigation](
            reason=f"the navigator was lost {retries} times (at most {MAX_NAVIGATION_RETRIES} retries)"))
        return
    log.warning("%s: the navigator was lost under the goal; waiting for Nav2 to be back (retry %d of %d)",
                type(state).__name__, retries, MAX_NAVIGATION_RETRIES)


class _RecoverNavigation(SmaccState):
    """Wait for Nav2's bonds (a respawned stack), then drive to the waypoint again (the subclass's
    SUCCESS target); ABORT if Nav2 does not come back within CbWaitNav2Nodes' timeout or after
    MAX_NAVIGATION_RETRIES retries. Not a state itself: the two below are."""

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNavigation, CbWaitNav2Nodes)
        cls.configure_orthogonal(OrKeyboard, CbDefaultKeyboardBehavior)

    def runtime_configure(self) -> None:
        _count_navigation_retry(self)


def _recovery_reactions(waypoint_state: str) -> list[Transition]:
    return [
        Transition(EvCbSuccess[CbWaitNav2Nodes, OrNavigation], waypoint_state, SUCCESS),
        Transition(EvCbFailure[CbWaitNav2Nodes, OrNavigation], "StFinalState", ABORT),
        Transition(EvMaxRetriesExceeded[CbWaitNav2Nodes, OrNavigation], "StFinalState", ABORT),
    ]


class StRecoverNavigation1(_RecoverNavigation):
    """Back to waypoint 1 once Nav2 is back."""

    reactions = _recovery_reactions("StNavigateToWaypoint1")


class StRecoverNavigation2(_RecoverNavigation):
    """Back to waypoint 2 once Nav2 is back."""

    reactions = _recovery_reactions("StNavigateToWaypoint2")


class StFinalState(SmaccState):
    """The end: no reactions, no behaviors."""

    def on_entry(self) -> None:
        log.info("Mission Complete")
