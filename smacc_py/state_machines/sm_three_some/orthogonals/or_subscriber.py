"""``OrSubscriber``: the machine's sensor client, ClSubscriber (``createClient<ClSubscriber>()``)."""

from __future__ import annotations

from smacc_py.core import Orthogonal
from smacc_py.state_machines.sm_three_some.clients.cl_subscriber import ClSubscriber


class OrSubscriber(Orthogonal):
    """One multirole sensor: every message is an EvTopicMessage[ClSubscriber, OrSubscriber]."""

    def on_initialize(self) -> None:
        self.create_client(ClSubscriber)
