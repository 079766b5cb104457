"""send_until_acknowledged: when a goal had to be sent twice and the server ran both copies for a
while, the caller's feedback callback hears the acknowledged copy only, in order, including the
feedback that arrived before the acknowledgement (CI run DS mixed two copies' feedback)."""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

from rclpy.task import Future

from ros_tools.runtime.actions import send_until_acknowledged


class TwoCopiesClient:
    """An action client whose server answers no copy until the test says so."""

    _action_name = "navigate_to_pose"

    def __init__(self) -> None:
        self.sent: list[tuple[Future, Any, Any]] = []  # (future, goal id, feedback callback)

    def send_goal_async(self, goal: Any, feedback_callback: Any = None, goal_uuid: Any = None) -> Future:
        future: Future = Future()
        self.sent.append((future, goal_uuid, feedback_callback))
        return future

    def feedback(self, copy: int, distance: float) -> None:
        _, goal_id, callback = self.sent[copy]
        callback(SimpleNamespace(goal_id=goal_id, feedback=SimpleNamespace(distance_remaining=distance)))


def test_feedback_of_the_acknowledged_copy_only() -> None:
    client = TwoCopiesClient()
    heard: list[float] = []
    script = iter(["no answer to the first copy", "both copies run, the second is answered"])

    def wait(answered: Any, seconds: float) -> bool:
        step = next(script)
        if step == "no answer to the first copy":
            client.feedback(0, 4.0)  # the server runs the first copy, whose answer is lost
            return False
        client.feedback(0, 3.0)
        client.feedback(1, 4.0)
        client.sent[1][0].set_result(SimpleNamespace(accepted=True))
        client.feedback(0, 2.0)
        return bool(answered())

    first = send_until_acknowledged(client, object(), 30.0, wait,
                                    lambda msg: heard.append(msg.feedback.distance_remaining))
    assert first is client.sent[1][0]
    client.feedback(1, 3.0)
    client.feedback(0, 1.0)
    client.feedback(1, 2.0)
    assert heard == [4.0, 3.0, 2.0]


def test_without_a_second_copy_all_feedback_passes() -> None:
    client = TwoCopiesClient()
    heard: list[float] = []

    def wait(answered: Any, seconds: float) -> bool:
        client.feedback(0, 5.0)
        client.sent[0][0].set_result(SimpleNamespace(accepted=True))
        return bool(answered())

    send_until_acknowledged(client, object(), 30.0, wait,
                            lambda msg: heard.append(msg.feedback.distance_remaining))
    client.feedback(0, 4.0)
    assert heard == [5.0, 4.0]
