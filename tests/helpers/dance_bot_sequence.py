"""sm_dance_bot's transitions as SMACC2's definition declares them, and a walk that checks a run's transition
log against them (tests/system/test_sm_dance_bot.py).

The tables below are written from the upstream headers (robosoft-ai/SMACC2,
``smacc2_sm_reference_library/sm_dance_bot/include/sm_dance_bot/``, abbreviated ``sm_dance_bot/`` in the
comments), each group naming its file, not from the port. Keys are what the machine publishes on
``/SmDanceBot/smacc/transition_log``: (source, declared target, tag). The source of a superstate's or a mode
state's own reaction is that state (``SsRadialPattern1`` for ENDLOOP, ``MsDanceBotRunMode`` for OVERHEAT), and
the target is the declared one (``SsRadialPattern1``, not its loop start; ``MsDanceBotRunMode`` for a deep
history transition). Upstream's untagged transitions carry the tag the port gives an untagged transition,
its event's default (as SMACC2 events name theirs in getDefaultTransitionType): SUCCESS for EvCbSuccess and
EvCountdownEnd, ABORT for EvCbFailure.

Why a walk and not one fixed list: the dance runs against Nav2's behavior server in turtlebot3_world, which
refuses a motion now and then (collision look-ahead: error codes 703, 714, 723); the state then takes its
declared failure transition, and the course after it shifts (StNavigateReverse4's failure goes straight to
StNavigateToWaypointsX, skipping StRotateDegrees5). The scripted overheating interrupts whatever state runs
at sim 60 s. So the walk starts in StAcquireSensors and accepts a logged transition only if the state the
machine is in declares it, with upstream's guards deciding between the declared ones: a loop start continues
while its superstate has iterations left and ends the loop after; StNavigateToWaypointsX's cursor picks the
waypoint event (TRANSITION_<i+1> for the i-th waypoint, in order). The only choices left to the run are the
ones the definition leaves to the world: a motion's (or a navigation's) success or failure transition, and
when the recovery mode interrupts. A transition missing, extra or out of order leaves the walk in a state
that does not declare the next one, and the check fails there. With every motion succeeding and no
overheating the walk is ``nominal_sequence()``.

Where the port deliberately differs from upstream (the port's docstrings say why), the tables follow the
port; each difference is marked "port:" with the module that documents it.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

Key = tuple[str, str, str]  # (source, declared target, tag) of one transition_log entry
Edge = tuple[str, str]  # (declared target, tag)

INITIAL_LEAF = "StAcquireSensors"  # sm_dance_bot/modestates/ms_dance_bot_run_mode.hpp: its initial state
FINAL_STATE = "StFinalState"
WAYPOINTS_X = "StNavigateToWaypointsX"
RUN_MODE, RECOVERY_MODE = "MsDanceBotRunMode", "MsDanceBotRecoveryMode"

# port (smacc_py/state_machines/sm_dance_bot/modestates.py): upstream's mode states switch only on
# EvGlobalError, which nothing posts, and the temperature alert has no transition. Here the alert enters the
# recovery mode (OVERHEAT) from any state of the run mode, and a normal reading resumes the state it left
# through deep history (RECOVERED; upstream's deep_history<MsDanceBotRunMode::LastDeepState>).
OVERHEAT: Key = (RUN_MODE, RECOVERY_MODE, "OVERHEAT")
RECOVERED: Key = (RECOVERY_MODE, RUN_MODE, "RECOVERED")


@dataclass(frozen=True)
class Loop:
    """A looping superstate: its loop start, the loop's first state, its iterations and where ENDLOOP goes."""

    superstate: str
    start: str
    first: str
    iterations: int
    then: str


def _motion(target: str, on_failure: str | None = None) -> tuple[Edge, Edge]:
    """A motion state's two transitions: EvCbSuccess → ``target`` (SUCCESS), EvCbFailure → ``on_failure``
    (ABORT), by default ``target`` too."""
    return (target, "SUCCESS"), (on_failure or target, "ABORT")


#: Every state's declared transitions but loop starts' and StNavigateToWaypointsX's (guarded: see the walk),
#: the nominal one first. EvGlobalError's transitions (st_acquire_sensors.hpp, st_event_count_down.hpp, the
#: mode states) are left out: nothing posts EvGlobalError, upstream or here, so the run never takes them.
REACTIONS: dict[str, tuple[Edge, ...]] = {
    # sm_dance_bot/states/st_acquire_sensors.hpp: EvAllGo of SrAllEventsGo (lidar, temperature, pose).
    "StAcquireSensors": (("StEventCountDown", "ON_SENSORS_AVAILABLE"),),
    # sm_dance_bot/states/st_event_count_down.hpp: EvCountdownEnd of SrEventCountdown(5), untagged.
    "StEventCountDown": ((WAYPOINTS_X, "SUCCESS"),),
    # sm_dance_bot/states/st_rotate_degrees_1.hpp, st_navigate_forward_1.hpp, st_rotate_degrees_2.hpp.
    "StRotateDegrees1": _motion("StNavigateForward1", WAYPOINTS_X),
    "StNavigateForward1": _motion("StRotateDegrees2", WAYPOINTS_X),
    "StRotateDegrees2": _motion(WAYPOINTS_X),
    # sm_dance_bot/states/st_navigate_reverse_1.hpp, st_rotate_degrees_3.hpp.
    "StNavigateReverse1": _motion("StRotateDegrees3", WAYPOINTS_X),
    "StRotateDegrees3": _motion(WAYPOINTS_X),
    # sm_dance_bot/states/st_rotate_degrees_4.hpp, st_navigate_reverse_2.hpp.
    "StRotateDegrees4": _motion("StNavigateReverse2", WAYPOINTS_X),
    "StNavigateReverse2": _motion(WAYPOINTS_X),
    # sm_dance_bot/states/st_navigate_reverse_4.hpp, st_navigate_forward_2.hpp, st_rotate_degrees_5.hpp.
    "StNavigateReverse4": _motion("StRotateDegrees5", WAYPOINTS_X),
    "StNavigateForward2": _motion("StRotateDegrees5", WAYPOINTS_X),
    "StRotateDegrees5": _motion(WAYPOINTS_X),
    # sm_dance_bot/states/st_rotate_degrees_6.hpp, st_navigate_reverse_3.hpp.
    "StRotateDegrees6": _motion("StNavigateReverse3", WAYPOINTS_X),
    "StNavigateReverse3": _motion("StNavigateToWaypoint1", WAYPOINTS_X),
    # sm_dance_bot/states/st_navigate_to_waypoint_1.hpp. port (st_navigation.py): both outcomes end in
    # StFinalState (new) instead of returning to StNavigateToWaypointsX, whose waypoints are all visited.
    "StNavigateToWaypoint1": _motion(FINAL_STATE),
    # sm_dance_bot/states/f_pattern_states/sti_fpattern_*.hpp: rotate (-90°) → ray → back → rotate (0°) →
    # pitch. port (ss_f_pattern.py): upstream declares failures only for Rotate2 (→ Forward2, ABORT), so a
    # refused motion stalls it; here every failure goes on to the next state (ABORT).
    "StiFPatternRotate1": _motion("StiFPatternForward1"),
    "StiFPatternForward1": _motion("StiFPatternReturn1"),
    "StiFPatternReturn1": _motion("StiFPatternRotate2"),
    "StiFPatternRotate2": _motion("StiFPatternForward2"),
    "StiFPatternForward2": _motion("StiFPatternStartLoop"),
}

# sm_dance_bot/states/radial_motion_states/sti_radial_{rotate,end_point,return}.hpp, declared once per radial
# superstate (namespaces SS1..SS3; the port's flat names carry the number). A failed rotation restarts the
# ray from the loop start (ABORT), a failed ray still returns (ABORT). port (ss_radial.py): a failed return
# goes on to the loop start (upstream: back to StiRadialEndPoint, for ever if the motion keeps being refused).
for _n in (1, 2, 3):
    REACTIONS[f"StiRadialRotate{_n}"] = _motion(f"StiRadialEndPoint{_n}", f"StiRadialLoopStart{_n}")
    REACTIONS[f"StiRadialEndPoint{_n}"] = _motion(f"StiRadialReturn{_n}")
    REACTIONS[f"StiRadialReturn{_n}"] = _motion(f"StiRadialLoopStart{_n}")

# sm_dance_bot/states/s_pattern_states/sti_spattern_{rotate,forward}_{1..4}.hpp: Rotate<k> → Forward<k> →
# Rotate<k+1>, Forward4 → the loop start. port (ss_s_pattern.py): upstream sends a failed leg back to the
# rotation before it and a failed rotation to the leg before it or to itself (a refused motion loops for
# ever); here every failure goes on to the next state (ABORT).
for _k in (1, 2, 3, 4):
    REACTIONS[f"StiSPatternRotate{_k}"] = _motion(f"StiSPatternForward{_k}")
    REACTIONS[f"StiSPatternForward{_k}"] = _motion(f"StiSPatternRotate{_k + 1}" if _k < 4
                                                   else "StiSPatternLoopStart")

#: The looping superstates, in the order the dance runs them. Iterations are the port's (waypoints.py: the
#: patterns shrunk to fit turtlebot3_world); the loop starts post EvLoopContinue → the first state
#: (CONTINUELOOP) while iterations remain, then EvLoopEnd, on which the superstate leaves (ENDLOOP).
LOOPS: tuple[Loop, ...] = (
    # sm_dance_bot/superstates/ss_radial_pattern_1.hpp (2 rays) and, for all three radial patterns,
    # states/radial_motion_states/sti_radial_loop_start.hpp. port (ss_radial.py): ENDLOOP → StRotateDegrees1,
    # upstream's commented-out alternative; its live transition goes to StNavigateReverse1 and leaves
    # StRotateDegrees1, StNavigateForward1 and StRotateDegrees2 unreachable.
    Loop("SsRadialPattern1", "StiRadialLoopStart1", "StiRadialRotate1", 2, "StRotateDegrees1"),
    # sm_dance_bot/superstates/ss_radial_pattern_2.hpp (4 rays).
    Loop("SsRadialPattern2", "StiRadialLoopStart2", "StiRadialRotate2", 4, "StNavigateReverse1"),
    # sm_dance_bot/superstates/ss_radial_pattern_3.hpp (2 rays: the "Updated upstream" side of the merge
    # conflict that file carries in total_iterations()).
    Loop("SsRadialPattern3", "StiRadialLoopStart3", "StiRadialRotate3", 2, "StRotateDegrees4"),
    # sm_dance_bot/superstates/ss_f_pattern_1.hpp, states/f_pattern_states/sti_fpattern_loop_start.hpp
    # (upstream 9 iterations, port 2).
    Loop("SsFPattern1", "StiFPatternStartLoop", "StiFPatternRotate1", 2, "StNavigateReverse4"),
    # sm_dance_bot/superstates/ss_s_pattern_1.hpp, states/s_pattern_states/sti_spattern_loop_start.hpp
    # (upstream 9 iterations, port 2). port (ss_s_pattern.py): ENDLOOP → StRotateDegrees6 (upstream:
    # StNavigateReverse3, leaving StRotateDegrees6, whose successor is StNavigateReverse3, unreachable).
    Loop("SsSPattern1", "StiSPatternLoopStart", "StiSPatternRotate1", 2, "StRotateDegrees6"),
)
_LOOP_BY_SUPERSTATE = {loop.superstate: loop for loop in LOOPS}
_LOOP_BY_START = {loop.start: loop for loop in LOOPS}

#: sm_dance_bot/states/st_navigate_to_waypoints_x.hpp: the transition of EvWaypoint<i>[ClNav2Z, OrNavigation],
#: i.e. of reaching the i-th waypoint of the plan, in order. port (st_navigation.py): EvWaypoint4 goes to
#: StNavigateForward2 (upstream: back to StNavigateToWaypointsX, so no transition reaches StNavigateForward2).
WAYPOINT_EDGES: tuple[Edge, ...] = (
    ("SsRadialPattern1", "TRANSITION_1"),
    ("SsRadialPattern2", "TRANSITION_2"),
    ("SsRadialPattern3", "TRANSITION_3"),
    ("SsFPattern1", "TRANSITION_4"),
    ("StNavigateForward2", "TRANSITION_5"),
    (WAYPOINTS_X, "TRANSITION_6"),
    ("SsSPattern1", "TRANSITION_7"),
)
#: Same file: EvCbFailure[CbNavigateNextWaypoint] retries the same waypoint (ABORT; the cursor advances only
#: when one is reached). port (st_navigation.py): entered with every waypoint visited, it goes home (new).
WAYPOINT_FAILED: Edge = (WAYPOINTS_X, "ABORT")
WAYPOINTS_DONE: Edge = ("StNavigateToWaypoint1", "ALL_VISITED")


class SequenceMismatch(AssertionError):
    """The log holds a transition the definition does not allow at that point, or ends early."""


class DanceBotWalk:
    """Where the machine is after the transitions taken so far, by the definition above, and what it may
    take next."""

    def __init__(self) -> None:
        self.leaf = INITIAL_LEAF
        self.started: dict[str, int] = {}  # iterations started per looping superstate (CONTINUELOOPs taken)
        self.cursor = 0  # index of the next waypoint of StNavigateToWaypointsX
        self.recovering = False  # in the recovery mode; ``leaf`` is the state deep history resumes
        self.recoveries = 0

    def allowed(self) -> list[Key]:
        """The transitions the definition allows now, the nominal one first (OVERHEAT last)."""
        if self.recovering:
            return [RECOVERED]
        if self.leaf == FINAL_STATE:
            return []
        return [*self._declared(), OVERHEAT]

    def _declared(self) -> list[Key]:
        loop = _LOOP_BY_START.get(self.leaf)
        if loop is not None:
            if self.started.get(loop.superstate, 0) < loop.iterations:
                return [(loop.start, loop.first, "CONTINUELOOP")]
            return [(loop.superstate, loop.then, "ENDLOOP")]
        if self.leaf == WAYPOINTS_X:
            if self.cursor >= len(WAYPOINT_EDGES):
                return [(WAYPOINTS_X, *WAYPOINTS_DONE)]
            return [(WAYPOINTS_X, *WAYPOINT_EDGES[self.cursor]), (WAYPOINTS_X, *WAYPOINT_FAILED)]
        return [(self.leaf, *edge) for edge in REACTIONS[self.leaf]]

    def take(self, key: Key) -> None:
        """Move along ``key``; SequenceMismatch if the definition does not allow it now."""
        allowed = self.allowed()
        if key not in allowed:
            raise SequenceMismatch(f"in {self.leaf}{' (recovery mode)' if self.recovering else ''}: {key} is "
                                   f"not allowed; the definition allows {allowed}")
        source, target, tag = key
        if key == OVERHEAT:
            self.recovering, self.recoveries = True, self.recoveries + 1
        elif key == RECOVERED:
            self.recovering = False  # deep history: back into the interrupted leaf
        elif tag == "CONTINUELOOP":
            superstate = _LOOP_BY_START[source].superstate
            self.started[superstate] = self.started.get(superstate, 0) + 1
            self.leaf = target
        else:
            if tag == "ENDLOOP":
                self.started[source] = 0
            if source == WAYPOINTS_X and (target, tag) not in (WAYPOINT_FAILED, WAYPOINTS_DONE):
                self.cursor += 1  # EvWaypoint<cursor>: the navigator's cursor moved on
            self.leaf = self._enter(target)

    @staticmethod
    def _enter(target: str) -> str:
        """The leaf a transition into ``target`` ends in (a looping superstate starts at its loop start)."""
        loop = _LOOP_BY_SUPERSTATE.get(target)
        return loop.start if loop is not None else target


def check_sequence(log: Sequence[Key]) -> DanceBotWalk:
    """Walk ``log`` from the start; it must end in StFinalState. SequenceMismatch names the first transition
    the definition does not allow, with the ones before it. Returns the walk (``recoveries``)."""
    walk = DanceBotWalk()
    for step, key in enumerate(log):
        try:
            walk.take(key)
        except SequenceMismatch as error:
            first = max(0, step - 8)
            before = "\n".join(f"  {i}: {k}" for i, k in enumerate(log[first:step], first))
            message = f"transition {step} of {len(log)}: {error}\nbefore it:\n{before}"
            raise SequenceMismatch(message) from None
    if walk.leaf != FINAL_STATE or walk.recovering:
        raise SequenceMismatch(f"the log ends after {len(log)} transitions in {walk.leaf} "
                               f"(recovering: {walk.recovering}), not in {FINAL_STATE}; next allowed: "
                               f"{walk.allowed()}")
    return walk


def walk_choosing(choose: Callable[[int, list[Key]], Key], limit: int = 1000) -> list[Key]:
    """The sequence a run takes when ``choose(step, allowed)`` picks each transition, up to StFinalState."""
    walk, taken = DanceBotWalk(), list[Key]()
    while walk.leaf != FINAL_STATE or walk.recovering:
        if len(taken) >= limit:
            raise SequenceMismatch(f"no {FINAL_STATE} after {limit} transitions")
        key = choose(len(taken), walk.allowed())
        walk.take(key)
        taken.append(key)
    return taken


def nominal_sequence() -> list[Key]:
    """Every motion succeeds, no overheating: the course the definition lays out."""
    return walk_choosing(lambda _step, allowed: allowed[0])
