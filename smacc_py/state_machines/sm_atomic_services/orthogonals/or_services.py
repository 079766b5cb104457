"""``OrServices``: a server and a client of the same service (``createClient<ClServiceServer>("service")``
and ``createClient<ClServiceClient>("service")``)."""

from __future__ import annotations

from smacc_py.core import Orthogonal
from smacc_py.state_machines.sm_atomic_services.clients import ClServiceClient, ClServiceServer

SERVICE = "service"  # relative, as upstream's: /service for a node in the root namespace


class OrServices(Orthogonal):
    """The machine serves ``SERVICE`` and could call it."""

    def on_initialize(self) -> None:
        self.create_client(ClServiceServer, SERVICE)
        self.create_client(ClServiceClient, SERVICE)
