"""``CbWaitActionServer``: EvCbSuccess once the orthogonal's action server is discovered.

SMACC2's ``CbWaitActionServer(timeout)``: it uses the action client of its own orthogonal (any
client with a ``CpActionClient`` component, such as a ``SmaccActionClientBase``) and polls
``server_ready()``; EvCbFailure after ``timeout_s`` s of machine clock. Discovery itself takes wall
time (a few hundred ms on localhost), so under a fast simulation give a generous timeout.
"""

from __future__ import annotations

from smacc_py.ros.client_behaviors.cb_outcome_base import CbOutcomeBase
from smacc_py.ros.components.cp_action_client import CpActionClient

DEFAULT_SERVER_WAIT_S = 10.0


class CbWaitActionServer(CbOutcomeBase):
    """Waits for the action server of the CpActionClient of its orthogonal (own orthogonal first)."""

    def __init__(self, timeout_s: float | None = DEFAULT_SERVER_WAIT_S) -> None:
        self.set_timeout(timeout_s)

    def start(self) -> None:
        self.action = self.requires_component(CpActionClient)
        self.poll()

    def poll(self) -> None:
        if self.action.server_ready():
            self.finish(True, action=self.action.action_name)

    def timeout_reason(self) -> str:
        return (f"CbWaitActionServer: action server '{self.action.action_name}' not available within "
                f"{self.timeout_s:g} s")
