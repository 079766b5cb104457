"""Client bases: SMACC2's ``smacc2::client_bases`` for writing your own clients.

* ``SmaccActionClientBase`` – one action server; EvActionFeedback/Result/Succeeded/Aborted/Cancelled.
* ``SmaccSubscriberClient`` – one topic; EvTopicMessage, EvTopicInitialMessage, EvTopicMessageTimeout.
* ``SmaccPublisherClient`` – one topic to publish on.
* ``SmaccServiceClient`` – one service to call; EvServiceResponse, EvServiceFailure.
* ``SmaccServiceServerClient`` – one service to serve; EvServiceRequestReceived.

Each base is a thin client over the components of ``smacc_py.ros.components``, which post the
events parameterised by the concrete client class and its orthogonal.
"""

from smacc_py.ros.client_bases.smacc_action_client_base import SmaccActionClientBase
from smacc_py.ros.client_bases.smacc_publisher_client import SmaccPublisherClient
from smacc_py.ros.client_bases.smacc_service_client import SmaccServiceClient
from smacc_py.ros.client_bases.smacc_service_server_client import (
    EvServiceRequestReceived,
    SmaccServiceServerClient,
)
from smacc_py.ros.client_bases.smacc_subscriber_client import EvTopicMessageTimeout, SmaccSubscriberClient

__all__ = [
    "EvServiceRequestReceived", "EvTopicMessageTimeout", "SmaccActionClientBase", "SmaccPublisherClient",
    "SmaccServiceClient", "SmaccServiceServerClient", "SmaccSubscriberClient",
]
