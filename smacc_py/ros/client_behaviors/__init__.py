"""Generic client behaviors: SMACC2's ``smacc2::client_behaviors``, none of which blocks.

* ``CbCallService`` – call a service on entry; EvCbSuccess(response) or EvCbFailure(reason).
* ``CbSequence`` – behaviors one after another; EvSequenceFinished and EvCbSuccess at the end.
* ``CbWaitTopicMessage`` – EvCbSuccess(msg) once a message passes an optional predicate.
* ``CbWaitActionServer`` – EvCbSuccess once the orthogonal's action server is discovered.
* ``CbWaitNode`` – EvCbSuccess once a node name is in the graph.
* ``CbRosLaunch`` – a process for the state's lifetime; EvCbFailure if it exits non-zero.
* ``CbSleepFor`` – EvCbSuccess after a duration of machine clock.

All but CbSequence derive ``CbOutcomeBase``: exactly one outcome, optional ``timeout_s`` on the node
clock (sim time under ``use_sim_time``), failures with a ``reason``.
"""

from smacc_py.ros.client_behaviors.cb_call_service import CbCallService
from smacc_py.ros.client_behaviors.cb_outcome_base import CbOutcomeBase
from smacc_py.ros.client_behaviors.cb_ros_launch import CbRosLaunch, ros2_launch_command
from smacc_py.ros.client_behaviors.cb_sequence import CbSequence
from smacc_py.ros.client_behaviors.cb_sleep_for import CbSleepFor
from smacc_py.ros.client_behaviors.cb_wait_action_server import CbWaitActionServer
from smacc_py.ros.client_behaviors.cb_wait_node import CbWaitNode
from smacc_py.ros.client_behaviors.cb_wait_topic_message import CbWaitTopicMessage

__all__ = [
    "CbCallService", "CbOutcomeBase", "CbRosLaunch", "CbSequence", "CbSleepFor", "CbWaitActionServer",
    "CbWaitNode", "CbWaitTopicMessage", "ros2_launch_command",
]
