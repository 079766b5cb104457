"""Client libraries (SMACC2's smacc2_client_library) and the generic pieces to write your own.

Shipped clients live in subpackages: ``cl_nav2z``, ``cl_ros2_timer`` (and its humble-era name
``cl_ros_timer``), ``cl_keyboard``, ``cl_battery``, ``cl_ros_publisher`` and ``cl_multirole_sensor``.
This package re-exports the last two and everything a SMACC2 user needs to write a client, under
SMACC2's names (the classes are defined in ``smacc_py.ros``; see the README section "Writing your own
client"):

Client bases (``smacc2::client_bases``):
    ``SmaccActionClientBase`` (SmaccActionClientBase<Action>), ``SmaccSubscriberClient``
    (SmaccSubscriberClient<Msg>), ``SmaccPublisherClient``, ``SmaccServiceClient``
    (SmaccServiceClient<Srv>), ``SmaccServiceServerClient`` (SmaccServiceServerClient<Srv>).
Components (``smacc2::client_core_components``):
    ``CpTopicSubscriber``, ``CpTopicPublisher``, ``CpActionClient``, ``CpServiceClient``, plus
    ``CpServiceServer`` and ``CpMessageTimeout`` (multirole_sensor_client's).
Behaviors (``smacc2::client_behaviors``):
    ``CbCallService`` (CbServiceCall), ``CbSequence``, ``CbWaitTopicMessage``,
    ``CbWaitActionServer``, ``CbWaitNode``, ``CbRosLaunch`` (CbRosLaunch2), ``CbSleepFor``, and
    their base ``CbOutcomeBase`` (no SMACC2 equivalent: one outcome, optional timeout).
Events beyond ``smacc_py.core``'s:
    ``EvTopicMessageTimeout`` (multirole_sensor_client's) and ``EvServiceRequestReceived`` (new: SMACC2
    only emits a signal when its service server is called).
Client libraries:
    ``ClRosPublisher`` with ``CbPublishOnce``, ``CbDefaultPublishLoop``, ``CbMuteBehavior``
    (``CbMutedBehavior``) – ros_publisher_client; ``ClMultiroleSensor`` with
    ``CbDefaultMultiRoleSensorBehavior`` – multirole_sensor_client.
"""

from smacc_py.clients.cl_multirole_sensor import CbDefaultMultiRoleSensorBehavior, ClMultiroleSensor
from smacc_py.clients.cl_ros_publisher import (
    CbDefaultPublishLoop,
    CbMuteBehavior,
    CbMutedBehavior,
    CbPublishOnce,
    ClRosPublisher,
)
from smacc_py.ros.action_client import GoalOutcome, GoalTicket
from smacc_py.ros.client_bases import (
    EvServiceRequestReceived,
    EvTopicMessageTimeout,
    SmaccActionClientBase,
    SmaccPublisherClient,
    SmaccServiceClient,
    SmaccServiceServerClient,
    SmaccSubscriberClient,
)
from smacc_py.ros.client_behaviors import (
    CbCallService,
    CbOutcomeBase,
    CbRosLaunch,
    CbSequence,
    CbSleepFor,
    CbWaitActionServer,
    CbWaitNode,
    CbWaitTopicMessage,
    ros2_launch_command,
)
from smacc_py.ros.components import (
    CpActionClient,
    CpMessageTimeout,
    CpServiceClient,
    CpServiceServer,
    CpTopicPublisher,
    CpTopicSubscriber,
    ServiceCall,
    SmaccSignal,
)

__all__ = [
    "CbCallService", "CbDefaultMultiRoleSensorBehavior", "CbDefaultPublishLoop", "CbMuteBehavior",
    "CbMutedBehavior", "CbOutcomeBase", "CbPublishOnce", "CbRosLaunch", "CbSequence", "CbSleepFor",
    "CbWaitActionServer", "CbWaitNode", "CbWaitTopicMessage", "ClMultiroleSensor", "ClRosPublisher",
    "CpActionClient", "CpMessageTimeout", "CpServiceClient", "CpServiceServer", "CpTopicPublisher",
    "CpTopicSubscriber", "EvServiceRequestReceived", "EvTopicMessageTimeout", "GoalOutcome", "GoalTicket",
    "ServiceCall", "SmaccActionClientBase", "SmaccPublisherClient", "SmaccServiceClient",
    "SmaccServiceServerClient", "SmaccSignal", "SmaccSubscriberClient", "ros2_launch_command",
]
