"""sm_atomic_services: SMACC2's service reference machine (smacc2_sm_reference_library/sm_atomic_services).

State1 waits 5 ticks of a 1 s ClRosTimer, then State2 waits for a call of the std_srvs/Empty service
``/service``, which the machine serves itself (ClServiceServer, a SmaccServiceServerClient): the
call's event, re-posted by State2's CbServiceServer, leads back to State1. OrServices also holds a
ClServiceClient of the same service, which no state uses (as upstream). Run it with
``smacc-run sm_atomic_services`` and call ``ros2py service call /service std_srvs/srv/Empty`` (or ROS 2's
``ros2 service call``) while it is in State2.

Its multirole-sensor sibling is sm_three_some, whose ClSubscriber is a ClMultiroleSensor.
"""

from smacc_py.state_machines.sm_atomic_services.sm_atomic_services import (
    NOMINAL_TRANSITIONS,
    SERVICE,
    SmAtomicServices,
)
from smacc_py.state_machines.sm_atomic_services.states import State1, State2

STATE_MACHINE = SmAtomicServices

__all__ = ["NOMINAL_TRANSITIONS", "SERVICE", "STATE_MACHINE", "SmAtomicServices", "State1", "State2"]
