"""Components of generic clients: one ROS endpoint each (SMACC2's client_core_components).

A "pure component" client (SMACC2 Jazzy style) is an ``ISmaccClient`` whose ``on_initialize`` creates
some of these; each posts its events parameterised by the owning client and its orthogonal, so the
client itself needs no code::

    class ClScanner(ISmaccClient):
        def on_initialize(self) -> None:
            self.create_component(CpTopicSubscriber, LaserScan, "/scan", qos_profile_sensor_data)
            self.create_component(CpMessageTimeout, 1.0)

Components: ``CpTopicSubscriber``, ``CpMessageTimeout`` (with ``EvTopicMessageTimeout``),
``CpTopicPublisher``, ``CpActionClient``, ``CpServiceClient`` (with ``ServiceCall``) and
``CpServiceServer`` (with ``EvServiceRequestReceived``).
"""

from smacc_py.ros.components.cp_action_client import CpActionClient
from smacc_py.ros.components.cp_message_timeout import CpMessageTimeout, EvTopicMessageTimeout
from smacc_py.ros.components.cp_service_client import CpServiceClient
from smacc_py.ros.components.cp_service_server import CpServiceServer, EvServiceRequestReceived
from smacc_py.ros.components.cp_topic_publisher import CpTopicPublisher
from smacc_py.ros.components.cp_topic_subscriber import CpTopicSubscriber
from smacc_py.ros.components.service_call import ServiceCall
from smacc_py.ros.components.signal import SmaccSignal

__all__ = [
    "CpActionClient", "CpMessageTimeout", "CpServiceClient", "CpServiceServer", "CpTopicPublisher",
    "CpTopicSubscriber", "EvServiceRequestReceived", "EvTopicMessageTimeout", "ServiceCall", "SmaccSignal",
]
