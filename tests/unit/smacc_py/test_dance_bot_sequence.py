"""The dance bot's transition walk (tests/helpers/dance_bot_sequence.py): what the system test
(tests/system/test_sm_dance_bot.py) checks a real run against must refuse a transition that is missing,
extra or out of order, and take the failures and the recovery upstream's definition allows."""

from __future__ import annotations

from tests.helpers.dance_bot_sequence import (
    OVERHEAT,
    RECOVERED,
    Key,
    SequenceMismatch,
    check_sequence,
    nominal_sequence,
    walk_choosing,
)


def _refused(sequence: list[Key]) -> bool:
    try:
        check_sequence(sequence)
    except SequenceMismatch:
        return True
    return False


def test_the_walk_follows_the_nominal_course_and_refuses_missing_extra_and_swapped_transitions() -> None:
    nominal = nominal_sequence()
    # 2 opening transitions; radial 1: 1 + 2 rays x 4 + ENDLOOP + 3 motions; radial 2: 1 + 4 x 4 + 1 + 2;
    # radial 3: 1 + 2 x 4 + 1 + 2; F: 1 + 2 x 6 + 1 + 2; waypoints 4 and 5: 3 + 1; S: 1 + 2 x 9 + 1 + 3.
    assert len(nominal) == 2 + 13 + 20 + 12 + 16 + 4 + 23
    assert nominal[-1] == ("StNavigateToWaypoint1", "StFinalState", "SUCCESS")
    check_sequence(nominal)
    for i in range(len(nominal)):
        assert _refused(nominal[:i] + nominal[i + 1:]), f"missing {i}: {nominal[i]}"
        assert _refused(nominal[:i + 1] + nominal[i:]), f"repeated {i}: {nominal[i]}"
        if i + 1 < len(nominal) and nominal[i] != nominal[i + 1]:
            swapped = [*nominal[:i], nominal[i + 1], nominal[i], *nominal[i + 2:]]
            assert _refused(swapped), f"swapped {i} and {i + 1}: {nominal[i]}, {nominal[i + 1]}"


def test_the_walk_takes_declared_failures_and_a_recovery_that_resumes_the_interrupted_state() -> None:
    failures = [("StiRadialRotate1", "StiRadialLoopStart1", "ABORT"),  # the first ray: no ray, no return
                ("StNavigateReverse4", "StNavigateToWaypointsX", "ABORT")]  # StRotateDegrees5 is skipped

    def choose(step: int, allowed: list[Key]) -> Key:
        if step == 40:
            return OVERHEAT
        failing = [key for key in allowed if key in failures]
        if failing:
            failures.remove(failing[0])  # each fails once
            return failing[0]
        return allowed[0]

    run = walk_choosing(choose)
    assert not failures and run[40:42] == [OVERHEAT, RECOVERED]
    assert check_sequence(run).recoveries == 1
    assert len(run) == len(nominal_sequence()) + 2 - 2 - 1  # the excursion; a ray's 4 become 2; 2 become 1
    # Deep history: after RECOVERED the machine goes on from where it was, not from the run mode's start.
    restarted = [*run[:42], ("StAcquireSensors", "StEventCountDown", "ON_SENSORS_AVAILABLE"), *run[42:]]
    assert _refused(restarted)
    # The upstream targets the port deliberately changed are refused (the tables follow the port).
    upstream_endloop = [("SsRadialPattern1", "StNavigateReverse1", "ENDLOOP") if key[0] == "SsRadialPattern1"
                        else key for key in run]
    assert _refused(upstream_endloop)
