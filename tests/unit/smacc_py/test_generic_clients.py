"""Generic clients, components and behaviors (smacc_py.ros.client_bases / components /
client_behaviors, cl_ros_publisher, cl_multirole_sensor) on a fake node and a manual clock."""

from __future__ import annotations

import functools
import sys
import time
from collections.abc import Callable
from typing import Any

import pytest
from nav2_msgs.action import Wait
from sensor_msgs.msg import Temperature
from std_msgs.msg import String
from std_srvs.srv import SetBool, Trigger

from smacc_py.clients import (
    CbCallService,
    CbDefaultMultiRoleSensorBehavior,
    CbDefaultPublishLoop,
    CbMuteBehavior,
    CbPublishOnce,
    CbRosLaunch,
    CbSequence,
    CbSleepFor,
    CbWaitActionServer,
    CbWaitNode,
    CbWaitTopicMessage,
    ClMultiroleSensor,
    ClRosPublisher,
    CpServiceClient,
    CpTopicPublisher,
    CpTopicSubscriber,
    EvServiceRequestReceived,
    EvTopicMessageTimeout,
    GoalOutcome,
    SmaccActionClientBase,
    SmaccPublisherClient,
    SmaccServiceClient,
    SmaccServiceServerClient,
    SmaccSubscriberClient,
)
from smacc_py.core import (
    EvActionAborted,
    EvActionCancelled,
    EvActionFeedback,
    EvActionResult,
    EvActionSucceeded,
    EvCbFailure,
    EvCbSuccess,
    EvSequenceFinished,
    EvServiceFailure,
    EvServiceResponse,
    EvTopicInitialMessage,
    EvTopicMessage,
    ISmaccClient,
    Orthogonal,
    SmaccAsyncClientBehavior,
    SmaccClientBehavior,
    SmaccEvent,
    SmaccObserver,
    SmaccState,
    SmaccStateMachineBase,
    Transition,
)
from tests.helpers.smacc_generic_fakes import GenericRig

WALL_GUARD_S = 10.0  # s: only a failure guard for waits on real processes and threads


class EvGo(SmaccEvent):
    """Leaves the state under test."""


class Recorder(SmaccObserver):
    def __init__(self) -> None:
        self.posted: list[SmaccEvent] = []

    def on_event_posted(self, sm: Any, event: SmaccEvent) -> None:
        self.posted.append(event)

    def of(self, event_type: type[SmaccEvent]) -> list[Any]:
        return [e for e in self.posted if type(e) is event_type]


def machine(make_clients: Callable[[Orthogonal], None], behavior: tuple[Any, ...] | None = None
            ) -> tuple[type[SmaccStateMachineBase], type[Orthogonal]]:
    """A machine whose one orthogonal holds what ``make_clients`` creates; StRun runs ``behavior``
    (class and arguments) and EvGo leaves it for StIdle."""

    class OrTest(Orthogonal):
        def on_initialize(self) -> None:
            make_clients(self)

    class SmTest(SmaccStateMachineBase):
        initial_state = "StRun"

        def on_initialize(self) -> None:
            self.create_orthogonal(OrTest)

    class StRun(SmaccState, parent=SmTest):
        reactions = (Transition(EvGo, "StIdle"),)

        @classmethod
        def static_configure(cls) -> None:
            if behavior is not None:
                cls.configure_orthogonal(OrTest, behavior[0], *behavior[1:])

    class StIdle(SmaccState, parent=SmTest):
        pass

    return SmTest, OrTest


def rig_for(make_clients: Callable[[Orthogonal], None], behavior: tuple[Any, ...] | None = None
            ) -> tuple[GenericRig, Recorder, type[Orthogonal]]:
    sm_type, or_type = machine(make_clients, behavior)
    rig = GenericRig(sm_type)
    recorder = Recorder()
    rig.sm.add_observer(recorder)
    rig.start()
    return rig, recorder, or_type


def behavior_of(rig: GenericRig, or_type: type[Orthogonal]) -> Any:
    return rig.sm.get_orthogonal(or_type).get_client_behaviors()[0]


# ----------------------------------------------------------------------------- client bases
class ClThermo(SmaccSubscriberClient):
    def __init__(self, timeout_s: float | None = None) -> None:
        super().__init__(Temperature, "/temperature", timeout_s=timeout_s)


def test_subscriber_client_posts_the_initial_message_once_then_every_message() -> None:
    rig, rec, or_type = rig_for(lambda o: o.create_client(ClThermo))
    first, second = Temperature(temperature=20.0), Temperature(temperature=21.0)
    assert rig.node.deliver("/temperature", first) == 1
    rig.node.deliver("/temperature", second)
    assert [e.msg for e in rec.of(EvTopicInitialMessage[ClThermo, or_type])] == [first]
    assert [e.msg for e in rec.of(EvTopicMessage[ClThermo, or_type])] == [first, second]
    assert rec.posted.index(rec.of(EvTopicInitialMessage[ClThermo, or_type])[0]) < rec.posted.index(
        rec.of(EvTopicMessage[ClThermo, or_type])[0])
    assert rig.sm.requires_client(ClThermo).last_message is second


def test_subscriber_timeout_counts_silence_on_the_machine_clock_and_rearms() -> None:
    rig, rec, or_type = rig_for(lambda o: o.create_client(ClThermo, timeout_s=2.0))
    timeouts = lambda: rec.of(EvTopicMessageTimeout[ClThermo, or_type])  # noqa: E731
    rig.poll(100.0)  # the first poll starts the watch (sim time may have jumped meanwhile)
    rig.poll(1.9)
    assert timeouts() == []
    rig.node.deliver("/temperature", Temperature())
    rig.poll(1.9)
    assert timeouts() == [], "a message restarts the watch"
    rig.poll(0.1)
    assert len(timeouts()) == 1 and timeouts()[0].silence_s == pytest.approx(2.0)
    assert timeouts()[0].topic == "/temperature"
    rig.poll(2.0)
    assert len(timeouts()) == 2, "continued silence times out again"


def test_subscriber_client_without_timeout_refuses_timeout_listeners() -> None:
    rig, _rec, _ = rig_for(lambda o: o.create_client(ClThermo))
    with pytest.raises(Exception, match="has no message timeout; give timeout_s"):
        rig.sm.requires_client(ClThermo).on_message_timeout(lambda s: None)


class ClChatter(SmaccPublisherClient):
    def __init__(self) -> None:
        super().__init__(String, "/chatter")


def test_publisher_client_publishes_and_names_a_wrong_message_type() -> None:
    rig, _rec, _ = rig_for(lambda o: o.create_client(ClChatter))
    client = rig.sm.requires_client(ClChatter)
    client.publish(String(data="hi"))
    assert [m.data for m in rig.node.publisher("/chatter").messages] == ["hi"]
    with pytest.raises(TypeError, match=r"CpTopicPublisher\('/chatter'\): the message must be a std_msgs"
                                        r".msg._string.String, got sensor_msgs.msg._temperature.Temperature"):
        client.publish(Temperature())


class ClArm(SmaccServiceClient):
    def __init__(self) -> None:
        super().__init__(SetBool, "/arm")


def test_service_client_posts_the_response_as_payload() -> None:
    rig, rec, or_type = rig_for(lambda o: o.create_client(ClArm))
    answers: list[Any] = []
    call = rig.sm.requires_client(ClArm).call(SetBool.Request(data=True), on_response=answers.append)
    assert call.sent
    request, _ = rig.node.client("/arm").pending[0]
    assert request.data is True
    rig.node.client("/arm").answer(lambda req, res: setattr(res, "message", f"armed={req.data}"))
    rig.dispatch()
    [event] = rec.of(EvServiceResponse[ClArm, or_type])
    assert event.response.message == "armed=True" and event.service == "/arm"
    assert answers == [event.response] and rec.of(EvServiceFailure[ClArm, or_type]) == []


def test_service_client_fails_when_the_server_never_appears_or_never_answers() -> None:
    rig, rec, or_type = rig_for(lambda o: o.create_client(ClArm))
    client = rig.sm.requires_client(ClArm)
    fake = rig.node.client("/arm")
    fake.ready = False
    client.call(timeout_s=1.0)
    rig.poll(0.9)
    assert rec.of(EvServiceFailure[ClArm, or_type]) == []
    rig.poll(0.1)
    [unavailable] = rec.of(EvServiceFailure[ClArm, or_type])
    assert unavailable.reason == "service '/arm' not available within 1 s"
    fake.ready = True
    client.call(timeout_s=1.0)
    rig.poll(1.0)
    silent = rec.of(EvServiceFailure[ClArm, or_type])[-1]
    assert silent.reason == "service '/arm' did not answer within 1 s"
    assert fake.withdrawn == [fake.pending[0][1]], "the unanswered request is withdrawn"


class ClStart(SmaccServiceServerClient):
    def __init__(self) -> None:
        super().__init__(Trigger, "/start")

    def on_request(self, request: Any, response: Any) -> Any:
        if getattr(self, "broken", False):
            raise RuntimeError("handler bug")
        response.success, response.message = True, "started"
        return response


def test_service_server_client_answers_and_posts_an_event_per_request() -> None:
    rig, rec, or_type = rig_for(lambda o: o.create_client(ClStart))
    response = rig.node.service("/start").call(Trigger.Request())
    assert (response.success, response.message) == (True, "started")
    rig.sm.requires_client(ClStart).broken = True
    failed = rig.node.service("/start").call(Trigger.Request())
    assert failed.success is False
    events = rec.of(EvServiceRequestReceived[ClStart, or_type])
    assert [e.response.message for e in events] == ["started", ""]
    assert not hasattr(events[0], "error") and events[1].error == "RuntimeError: handler bug"


class ClWait(SmaccActionClientBase):
    def __init__(self) -> None:
        super().__init__(Wait, "wait")


def test_action_client_posts_feedback_result_and_outcome_for_its_goals() -> None:
    rig, rec, or_type = rig_for(lambda o: o.create_client(ClWait))
    client = rig.sm.requires_client(ClWait)
    done: list[Any] = []
    client.send_goal(Wait.Goal(), on_done=done.append)
    rig.action_client().feedback(Wait.Feedback())
    rig.action_client().finish(GoalOutcome.SUCCEEDED, Wait.Result(error_msg=""))
    assert len(rec.of(EvActionFeedback[ClWait, or_type])) == 1
    [result] = rec.of(EvActionResult[ClWait, or_type])
    assert result.outcome is GoalOutcome.SUCCEEDED and result.action == "wait"
    assert len(rec.of(EvActionSucceeded[ClWait, or_type])) == 1 and len(done) == 1
    client.send_goal(Wait.Goal())
    rig.action_client().finish(GoalOutcome.REJECTED)
    [rejected] = rec.of(EvActionAborted[ClWait, or_type])
    assert rejected.error_msg == "wait goal rejected"


def test_action_client_cancels_on_request_and_abandoned_goals_post_nothing() -> None:
    rig, rec, or_type = rig_for(lambda o: o.create_client(ClWait))
    client = rig.sm.requires_client(ClWait)
    ticket = client.send_goal(Wait.Goal())
    assert client.active_goals() == [ticket]
    client.cancel_goal()
    assert ticket.cancel_requested
    rig.action_client().finish(GoalOutcome.CANCELED)
    assert len(rec.of(EvActionCancelled[ClWait, or_type])) == 1
    abandoned = client.send_goal(Wait.Goal())
    abandoned.abandon()
    rig.action_client().finish(GoalOutcome.CANCELED)
    assert len(rec.of(EvActionResult[ClWait, or_type])) == 1, "no events for an abandoned goal"
    with pytest.raises(TypeError, match=r"CpActionClient\('wait'\): the goal must be a nav2_msgs"):
        client.send_goal(Wait.Result())


class ClPure(ISmaccClient):
    """A "pure component" client: it only composes components."""

    def on_initialize(self) -> None:
        self.create_component(CpTopicSubscriber, String, "/in")
        self.create_component(CpTopicPublisher, String, "/out")
        self.create_component(CpServiceClient, Trigger, "/trigger")


def test_components_post_events_parameterised_by_their_client() -> None:
    rig, rec, or_type = rig_for(lambda o: o.create_client(ClPure))
    rig.node.deliver("/in", String(data="x"))
    rig.sm.requires_component(CpTopicPublisher).publish(String(data="y"))
    rig.sm.requires_component(CpServiceClient).call(Trigger.Request())
    rig.node.client("/trigger").answer()
    assert [e.msg.data for e in rec.of(EvTopicMessage[ClPure, or_type])] == ["x"]
    assert [m.data for m in rig.node.publisher("/out").messages] == ["y"]
    assert len(rec.of(EvServiceResponse[ClPure, or_type])) == 1


@pytest.mark.parametrize(("build", "message"), [
    (lambda: SmaccServiceClient(Trigger, ""), r"SmaccServiceClient\(''\): the service name is empty"),
    (lambda: SmaccServiceClient(String, "/x"), r"expected a ROS service class .* got String"),
    (lambda: SmaccSubscriberClient(Trigger, "/x"), r"expected a ROS message class .* got Trigger"),
    (lambda: SmaccSubscriberClient(String(), "/x"), r"got std_msgs.msg.String\(data=''\) \(a String\)"),
    (lambda: SmaccSubscriberClient(String, "/x", timeout_s=-1.0), r"timeout_s must be > 0 s .* got -1.0"),
    (lambda: SmaccPublisherClient(String, "/x", qos=0), r"qos depth must be >= 1, got 0"),
    (lambda: SmaccActionClientBase(Trigger, "/x"), r"expected a ROS action class .* got Trigger"),
    (lambda: CbCallService(Trigger, "/x", SetBool.Request()), r"CbCallService\('/x'\): the request must"),
    (lambda: CbWaitTopicMessage(String, " "), r"CbWaitTopicMessage\(' '\): the topic name is empty"),
    (lambda: CbSleepFor(0), r"CbSleepFor: duration_s must be > 0 s and finite, got 0"),
    (lambda: CbWaitNode(""), r"CbWaitNode: the node name is empty"),
    (lambda: CbRosLaunch("ros2 launch x y"), r"CbRosLaunch: command must be a non-empty list"),
    (lambda: CbPublishOnce("hello"), r"CbPublishOnce: expected a ROS message instance, got 'hello'"),
    (lambda: CbSequence([42]), r"CbSequence step 0: 42 is not a behavior class or factory"),
])
def test_bad_arguments_fail_at_construction_naming_the_object_and_value(build: Any, message: str) -> None:
    with pytest.raises((TypeError, ValueError), match=message):
        build()


# ----------------------------------------------------------------------------- behaviors
def test_cb_call_service_succeeds_with_the_response_and_fails_on_timeout_or_rejection() -> None:
    ok = rig_for(lambda o: None, (CbCallService, SetBool, "/arm", SetBool.Request(data=True)))
    rig, rec, or_type = ok
    rig.node.client("/arm").answer(lambda req, res: setattr(res, "success", req.data))
    rig.dispatch()
    [success] = rec.of(EvCbSuccess[CbCallService, or_type])
    assert success.response.success is True

    rig, rec, or_type = rig_for(lambda o: None, (CbCallService, Trigger, "/t", None, 2.0))
    rig.poll(2.0)
    [failure] = rec.of(EvCbFailure[CbCallService, or_type])
    assert failure.reason == "CbCallService: service '/t' did not answer within 2 s"

    rig, rec, or_type = rig_for(lambda o: None, (CbCallService, Trigger, "/t", None, 2.0,
                                                 lambda res: res.success))
    rig.node.client("/t").answer()
    rig.dispatch()
    [rejected] = rec.of(EvCbFailure[CbCallService, or_type])
    assert "the response was rejected" in rejected.reason


def test_cb_call_service_abandons_its_call_and_client_on_exit() -> None:
    rig, rec, or_type = rig_for(lambda o: None, (CbCallService, Trigger, "/t"))
    fake = rig.node.client("/t")
    rig.sm.post_event(EvGo)
    rig.dispatch()
    assert fake.destroyed and fake.withdrawn == [fake.pending[0][1]]
    fake.answer()
    rig.dispatch()
    assert rec.of(EvCbSuccess[CbCallService, or_type]) == []


def test_cb_sleep_for_succeeds_after_its_duration_of_machine_clock() -> None:
    rig, rec, or_type = rig_for(lambda o: None, (CbSleepFor, 1.5))
    rig.poll(1.4)
    assert rec.of(EvCbSuccess[CbSleepFor, or_type]) == []
    rig.poll(0.1)
    [event] = rec.of(EvCbSuccess[CbSleepFor, or_type])
    assert event.slept_s == pytest.approx(1.5)


def test_cb_wait_topic_message_filters_with_the_predicate_and_unsubscribes_on_exit() -> None:
    predicate = lambda m: m.temperature > 30.0  # noqa: E731
    rig, rec, or_type = rig_for(lambda o: None, (CbWaitTopicMessage, Temperature, "/t", predicate))
    rig.node.deliver("/t", Temperature(temperature=10.0))
    assert rec.of(EvCbSuccess[CbWaitTopicMessage, or_type]) == []
    hot = Temperature(temperature=31.0)
    rig.node.deliver("/t", hot)
    rig.node.deliver("/t", Temperature(temperature=40.0))
    assert [e.msg for e in rec.of(EvCbSuccess[CbWaitTopicMessage, or_type])] == [hot]
    rig.sm.post_event(EvGo)
    rig.dispatch()
    assert rig.node.deliver("/t", hot) == 0


def test_cb_wait_topic_message_fails_on_timeout_and_on_a_raising_predicate() -> None:
    rig, rec, or_type = rig_for(lambda o: None, (CbWaitTopicMessage, String, "/s", None, 3.0))
    rig.poll(3.0)
    [timeout] = rec.of(EvCbFailure[CbWaitTopicMessage, or_type])
    assert timeout.reason == "CbWaitTopicMessage('/s'): no accepted message within 3 s (0 received)"
    rig, rec, or_type = rig_for(lambda o: None, (CbWaitTopicMessage, String, "/s", lambda m: 1 / 0))
    rig.node.deliver("/s", String())
    [failure] = rec.of(EvCbFailure[CbWaitTopicMessage, or_type])
    assert "the predicate raised ZeroDivisionError" in failure.reason


def test_cb_wait_action_server_succeeds_once_discovered_else_fails_after_timeout() -> None:
    rig, rec, or_type = rig_for(lambda o: o.create_client(ClWait), (CbWaitActionServer, 5.0))
    assert len(rec.of(EvCbSuccess[CbWaitActionServer, or_type])) == 1
    sm_type, or_type = machine(lambda o: o.create_client(ClWait), (CbWaitActionServer, 5.0))
    rig = GenericRig(sm_type)
    rec = Recorder()
    rig.sm.add_observer(rec)
    rig.sm.initialize()
    rig.action_client().ready = False
    rig.start()
    rig.poll(4.9)
    assert rec.of(EvCbFailure[CbWaitActionServer, or_type]) == []
    rig.poll(0.1)
    [failure] = rec.of(EvCbFailure[CbWaitActionServer, or_type])
    assert failure.reason == "CbWaitActionServer: action server 'wait' not available within 5 s"


@pytest.mark.parametrize("name", ["amcl", "/robot1/amcl"])
def test_cb_wait_node_succeeds_when_the_node_appears(name: str) -> None:
    rig, rec, or_type = rig_for(lambda o: None, (CbWaitNode, name, 10.0))
    rig.poll(0.2)
    assert rec.of(EvCbSuccess[CbWaitNode, or_type]) == []
    rig.node.graph.append(("amcl", "/robot1"))
    rig.poll(0.2)
    assert [e.node for e in rec.of(EvCbSuccess[CbWaitNode, or_type])] == [name]


def test_cb_wait_node_fails_after_its_timeout() -> None:
    rig, rec, or_type = rig_for(lambda o: None, (CbWaitNode, "/ghost", 1.0))
    rig.poll(1.0)
    [failure] = rec.of(EvCbFailure[CbWaitNode, or_type])
    assert failure.reason == "CbWaitNode: node '/ghost' not in the graph within 1 s"


def _poll_until(rig: GenericRig, predicate: Callable[[], bool], what: str) -> None:
    deadline = time.monotonic() + WALL_GUARD_S
    while not predicate():
        assert time.monotonic() < deadline, f"timed out waiting for {what}"
        rig.poll(0.05)
        time.sleep(0.01)


def _python(code: str) -> list[str]:
    return [sys.executable, "-c", code]


@pytest.mark.parametrize(("code", "ok"), [("pass", True), ("raise SystemExit(3)", False)])
def test_cb_ros_launch_reports_the_exit_status(code: str, ok: bool) -> None:
    rig, rec, or_type = rig_for(lambda o: None, (CbRosLaunch, _python(code)))
    outcome = lambda: rec.of(EvCbSuccess[CbRosLaunch, or_type]) + rec.of(EvCbFailure[CbRosLaunch, or_type])  # noqa: E731
    _poll_until(rig, outcome, "the process to end")
    [event] = outcome()
    assert isinstance(event, EvCbSuccess) is ok
    if not ok:
        assert event.returncode == 3 and "exited with status 3" in event.reason


def test_cb_ros_launch_stops_its_process_when_the_state_exits() -> None:
    rig, rec, or_type = rig_for(lambda o: None, (CbRosLaunch, _python("import time; time.sleep(60)")))
    behavior = behavior_of(rig, or_type)
    rig.sm.post_event(EvGo)
    rig.dispatch()
    assert behavior.process.wait(WALL_GUARD_S) != 0
    assert rec.of(EvCbSuccess[CbRosLaunch, or_type]) == rec.of(EvCbFailure[CbRosLaunch, or_type]) == []


def test_cb_ros_launch_fails_when_the_command_cannot_start() -> None:
    _rig, rec, or_type = rig_for(lambda o: None, (CbRosLaunch, ["/nonexistent/launcher"]))
    [failure] = rec.of(EvCbFailure[CbRosLaunch, or_type])
    assert "cannot start ['/nonexistent/launcher']" in failure.reason


class CbShout(SmaccClientBehavior):
    """A step that posts an event of its own, then succeeds."""

    def on_entry(self) -> None:
        self.post_event(EvGo)  # forwarded to the machine: it leaves the state
        self.post_success_event()


class CbAsyncStep(SmaccAsyncClientBehavior):
    def on_entry(self) -> None:
        pass  # returning posts EvCbFinished, which completes the step


def test_cb_sequence_runs_its_steps_in_order_then_posts_finished_and_success() -> None:
    steps = [functools.partial(CbSleepFor, 1.0), functools.partial(CbSleepFor, 2.0)]
    rig, rec, or_type = rig_for(lambda o: None, (CbSequence, steps))
    sequence = behavior_of(rig, or_type)
    assert (sequence.index, type(sequence.current)) == (0, CbSleepFor)
    rig.poll(1.0)
    assert sequence.index == 1 and rec.of(EvCbSuccess[CbSleepFor, or_type]) == [], "steps' events stay inside"
    rig.poll(1.9)
    assert sequence.index == 1
    rig.poll(0.1)
    state = type(rig.sm.current_state)
    assert len(rec.of(EvSequenceFinished[state])) == 1
    [success] = rec.of(EvCbSuccess[CbSequence, or_type])
    assert success.steps == 2 and sequence.current is None


def test_cb_sequence_then_chains_async_steps_and_stops_at_a_failing_step() -> None:
    class CbChain(CbSequence):
        def __init__(self) -> None:
            super().__init__()
            self.then(CbAsyncStep).then(CbWaitTopicMessage, String, "/s", None, 1.0).then(CbAsyncStep)

    rig, rec, or_type = rig_for(lambda o: None, (CbChain,))
    running = behavior_of(rig, or_type)
    _poll_until(rig, lambda: running.index == 1, "the async step to finish")
    rig.poll(1.0)
    [failure] = rec.of(EvCbFailure[CbChain, or_type])
    assert failure.step == 1 and failure.behavior == "CbWaitTopicMessage"
    assert failure.reason.startswith("CbSequence step 1 (CbWaitTopicMessage): CbWaitTopicMessage('/s'): no")
    assert running.index == 1 and rec.of(EvCbSuccess[CbChain, or_type]) == []


def test_cb_sequence_forwards_other_events_and_exits_its_running_step() -> None:
    rig, _rec, _or = rig_for(lambda o: None, (CbSequence, [CbShout, functools.partial(
        CbWaitTopicMessage, String, "/s")]))
    assert rig.state() == "StIdle", "the step's own event reached the machine"
    assert rig.node.deliver("/s", String()) == 0, "the running step was exited with the state"


def test_ros_publisher_behaviors_publish_once_loop_or_stay_mute() -> None:
    publisher = lambda o: o.create_client(ClRosPublisher, String, "/say")  # noqa: E731
    rig, rec, or_type = rig_for(publisher, (CbPublishOnce, String(data="a")))
    assert [m.data for m in rig.node.publisher("/say").messages] == ["a"]
    assert len(rec.of(EvCbSuccess[CbPublishOnce, or_type])) == 1

    rig, _rec, _ = rig_for(lambda o: o.create_client(ClRosPublisher, String, "/say"),
                           (CbDefaultPublishLoop, String(data="b"), 1.0))
    for _ in range(5):
        rig.poll(0.5)
    assert len(rig.node.publisher("/say").messages) == 3, "on entry, then every 1 s of machine clock"

    rig, _rec, _ = rig_for(lambda o: o.create_client(ClRosPublisher, String, "/say"), (CbMuteBehavior,))
    rig.poll(1.0)
    assert rig.node.publisher("/say").messages == []


def test_publish_behavior_with_the_wrong_message_type_fails_on_entry() -> None:
    rig, rec, or_type = rig_for(lambda o: o.create_client(ClRosPublisher, String, "/say"),
                                (CbPublishOnce, Temperature()))
    assert rig.node.publisher("/say").messages == []
    assert rec.of(EvCbSuccess[CbPublishOnce, or_type]) == []


class CbCountingSensor(CbDefaultMultiRoleSensorBehavior):
    def on_message_callback(self, msg: Any) -> None:
        self.count = getattr(self, "count", 0) + 1


def test_multirole_sensor_behavior_reposts_messages_and_timeouts_as_its_own() -> None:
    rig, rec, or_type = rig_for(lambda o: o.create_client(ClMultiroleSensor, Temperature, "/t", 1.0),
                                (CbCountingSensor,))
    rig.node.deliver("/t", Temperature())
    rig.poll(0.0)
    rig.poll(1.0)
    assert len(rec.of(EvTopicInitialMessage[CbCountingSensor, or_type])) == 1
    assert len(rec.of(EvTopicMessage[CbCountingSensor, or_type])) == 1
    assert len(rec.of(EvTopicMessage[ClMultiroleSensor, or_type])) == 1, "the client posts as well"
    assert len(rec.of(EvTopicMessageTimeout[CbCountingSensor, or_type])) == 1
    assert len(rec.of(EvTopicMessageTimeout[ClMultiroleSensor, or_type])) == 1
    assert behavior_of(rig, or_type).count == 1
    rig.sm.post_event(EvGo)
    rig.dispatch()
    rig.node.deliver("/t", Temperature())
    assert len(rec.of(EvTopicMessage[CbCountingSensor, or_type])) == 1, "disconnected on exit"
    assert len(rec.of(EvTopicMessage[ClMultiroleSensor, or_type])) == 2
