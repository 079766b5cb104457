"""SMACC2-compatible introspection of a running machine: topics, QoS for late joiners, history service."""

from __future__ import annotations

import pytest
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from smacc2_msgs.msg import SmaccEvent, SmaccStateMachine, SmaccStatus, SmaccTransitionLogEntry
from smacc2_msgs.srv import SmaccGetTransitionHistory

from navsuite_testing.ros import spin_until, wait_until
from smacc_py.state_machines.sm_nav2_test_1 import NOMINAL_TRANSITIONS, SmNav2Test1

pytestmark = pytest.mark.ros

LATCHED = QoSProfile(
    depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL
)
LOG = QoSProfile(
    depth=100, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL
)

STATES = [
    "StAllSensorsGo",
    "StSetInitialPose",
    "StNavigateToWaypoint1",
    "StRotate",
    "StNavigateToWaypoint2",
    "StFinalState",
    "StRecoverNavigation1",  # beyond the tutorial: a lost navigator is retried (issue 45)
    "StRecoverNavigation2",
]


def test_topics_and_history_service_describe_the_mission(stack, ros_context) -> None:  # type: ignore[no-untyped-def]
    _fake, runtime = stack(SmNav2Test1)
    wait_until(lambda: runtime.sm.current_state_names() == ["StFinalState"], 30.0, "the mission to end")
    # A viewer that starts after the mission still gets structure, status and the transition log.
    probe = rclpy.create_node("introspection_probe", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(probe)
    got: dict[str, list] = {"description": [], "status": [], "log": [], "events": []}
    try:
        prefix = "/SmNav2Test1/smacc"
        probe.create_subscription(
            SmaccStateMachine, f"{prefix}/state_machine_description", got["description"].append, LATCHED
        )
        probe.create_subscription(SmaccStatus, f"{prefix}/status", got["status"].append, LATCHED)
        probe.create_subscription(SmaccTransitionLogEntry, f"{prefix}/transition_log", got["log"].append, LOG)
        probe.create_subscription(SmaccEvent, f"{prefix}/event_log", got["events"].append, 10)
        client = probe.create_client(SmaccGetTransitionHistory, f"{prefix}/transition_log_history")
        spin_until(
            executor,
            lambda: got["description"] and got["status"] and len(got["log"]) >= 5,
            10.0,
            "late-joiner description, status and transition log",
        )

        description = got["description"][-1]
        assert sorted(s.name for s in description.states) == sorted(STATES)
        rotate = next(s for s in description.states if s.name == "StRotate")
        assert [o.name for o in rotate.orthogonals] == ["OrNavigation", "OrKeyboard"]
        assert rotate.orthogonals[0].client_behavior_names == ["CbPureSpinning"]
        assert rotate.orthogonals[0].client_names == ["ClNav2Z"]
        assert {(t.destiny_state_name, t.transition_type) for t in rotate.transitions} == {
            ("StNavigateToWaypoint2", "SUCCESS"),
            ("StFinalState", "ABORT"),
        }

        assert got["status"][-1].current_states == ["StFinalState"]
        assert "localization_attempt_count" in got["status"][-1].global_variable_names

        log = got["log"][-5:]
        assert [
            (e.transition.source_state_name, e.transition.destiny_state_name, e.transition.transition_type)
            for e in log
        ] == list(NOMINAL_TRANSITIONS)
        assert log[0].transition.event.event_type == "EvCbSuccess"
        assert log[0].transition.event.event_source == "CbWaitNav2Nodes"
        assert log[0].transition.event.event_object_tag == "OrNavigation"
        assert all(e.transition.index >= 0 for e in log)  # matched to the static description
        assert log[-1].timestamp.sec >= 1000  # stamped on sim time

        assert client.wait_for_service(timeout_sec=5.0)
        future = client.call_async(SmaccGetTransitionHistory.Request())
        spin_until(executor, future.done, 5.0, "the transition history response")
        history = future.result().history
        assert [(h.transition.source_state_name, h.transition.transition_type) for h in history] == [
            (s, t) for s, _, t in NOMINAL_TRANSITIONS
        ]
    finally:
        executor.shutdown()
        probe.destroy_node()


def test_event_log_and_status_follow_a_key_press(stack, ros_context) -> None:  # type: ignore[no-untyped-def]
    from std_msgs.msg import UInt16

    # No bonds: only the key leaves StAllSensorsGo. No AMCL answer: StSetInitialPose stays the current
    # state long enough to be seen (with an answer it moves on within a tick, before a status is read).
    _fake, runtime = stack(SmNav2Test1, bond_nodes=(), amcl_echo=False)
    probe = rclpy.create_node("event_probe", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(probe)
    events: list[SmaccEvent] = []
    statuses: list[SmaccStatus] = []
    try:
        probe.create_subscription(SmaccEvent, "/SmNav2Test1/smacc/event_log", events.append, 100)
        probe.create_subscription(SmaccStatus, "/SmNav2Test1/smacc/status", statuses.append, LATCHED)
        pub = probe.create_publisher(UInt16, "/keyboard_unicode", 10)
        spin_until(
            executor,
            lambda: (
                pub.get_subscription_count() > 0
                and runtime.sm.current_state is not None
                and probe.count_publishers("/SmNav2Test1/smacc/event_log") > 0
            ),
            10.0,
            "the machine to run",
        )
        spin_until(executor, lambda: bool(statuses), 5.0, "a status message")
        pub.publish(UInt16(data=ord("N")))
        spin_until(
            executor,
            lambda: any(e.label == "EvKeyPressN[CbDefaultKeyboardBehavior, OrKeyboard]" for e in events),
            10.0,
            "EvKeyPressN on the event log",
        )
        spin_until(
            executor,
            lambda: statuses[-1].current_states == ["StSetInitialPose"],
            10.0,
            "the status to show StSetInitialPose",
        )
        key_event = next(e for e in events if e.event_type == "EvKeyPressN")
        assert (key_event.event_source, key_event.event_object_tag) == (
            "CbDefaultKeyboardBehavior",
            "OrKeyboard",
        )
    finally:
        executor.shutdown()
        probe.destroy_node()
