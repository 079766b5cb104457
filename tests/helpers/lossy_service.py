"""A real rclpy service that loses responses, as rmw_fastrtps does while the server's response
writer has not yet matched the client's reader (see ros_tools.runtime.requests)."""

from __future__ import annotations

from typing import Any


class LoseResponses:
    """Wraps ``service`` (an rclpy ``Service``): the requests are handled as usual, and the responses
    to the first ``count`` of them are dropped. ``sent`` and ``lost`` count responses."""

    def __init__(self, service: Any, count: int) -> None:
        self.count = count
        self.sent = 0
        self.lost = 0
        self._send = service.send_response
        service.send_response = self._maybe_send

    def _maybe_send(self, response: Any, header: Any) -> None:
        if self.lost < self.count:
            self.lost += 1
            return
        self.sent += 1
        self._send(response, header)
