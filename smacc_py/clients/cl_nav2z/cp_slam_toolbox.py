"""``CpSlamToolbox``: pauses and resumes the SLAM node's integration of new scans (SMACC2's CpSlamToolbox).

SMACC2's component only remembers whether it last asked slam_toolbox to pause or to resume:
slam_toolbox's ``/slam_toolbox/pause_new_measurements`` (slam_toolbox/srv/Pause, an empty request)
toggles, and says nothing about the state it left. nav_stack's SLAM node (nav_stack/ros/slam/slam_node.py)
serves ``/slam/pause_new_measurements`` as std_srvs/SetBool instead (``data`` true pauses, false
resumes; the map and map → odom stay published while paused). A SetBool request names the state it
wants, so asking twice is harmless and the component's ``state`` is set from the node's answer, never
toggled blind: a pause that failed leaves ``state`` as it was.

The component owns the service client (so a test substitutes only ``make_client``); CbPauseSlam and
CbResumeSlam use it.
"""

from __future__ import annotations

import enum
import logging
from collections.abc import Callable
from typing import Any

from std_srvs.srv import SetBool

from smacc_py.clients.cl_nav2z.service_caller import DEFAULT_CALL_TIMEOUT_S, ServiceCaller
from smacc_py.ros.components.checks import check_duration, check_name
from smacc_py.ros.components.service_call import ServiceCall

PAUSE_SERVICE = "/slam/pause_new_measurements"  # nav_stack's SLAM node (std_srvs/SetBool)

_log = logging.getLogger("smacc_py")

#: ``on_done(succeeded, detail)``: detail is the node's message, or why the call failed.
SlamDoneCallback = Callable[[bool, str], None]


class SlamToolboxState(enum.Enum):
    """What the SLAM node was last told and confirmed (SMACC2: ``CpSlamToolbox::SlamToolboxState``)."""

    RESUMED = "resumed"
    PAUSED = "paused"


class CpSlamToolbox(ServiceCaller):
    """Client of the SLAM node's pause service; ``state`` starts RESUMED, as the node starts mapping.

    Args:
        service_name: the std_srvs/SetBool pause service.
        timeout_s: s (machine and wall clock) a request may take, discovery included.
    """

    def __init__(self, service_name: str = PAUSE_SERVICE, timeout_s: float = DEFAULT_CALL_TIMEOUT_S) -> None:
        super().__init__()
        self.service_name = check_name("CpSlamToolbox", "service", service_name)
        self.timeout_s = check_duration("CpSlamToolbox", "timeout_s", timeout_s)
        self.state = SlamToolboxState.RESUMED
        self._client: Any = None

    def on_initialize(self) -> None:
        self._client = self.make_client(SetBool, self.service_name)

    def set_paused(self, paused: bool, on_done: SlamDoneCallback) -> ServiceCall:
        """Ask the node to pause (True) or resume (False) integrating scans; never blocks.

        ``on_done(True, message)`` runs on the executor thread once the node accepted (``state`` is
        updated first); ``on_done(False, reason)`` once it refused, or did not answer in ``timeout_s``.
        """
        wanted = SlamToolboxState.PAUSED if paused else SlamToolboxState.RESUMED

        def answered(response: Any) -> None:
            if response.success:
                self.state = wanted
                on_done(True, response.message)
            else:
                on_done(False, f"'{self.service_name}' refused to switch to {wanted.value}: "
                               f"{response.message}")

        _log.info("CpSlamToolbox: asking '%s' to switch to %s", self.service_name, wanted.value)
        return self.call_service(self._client, SetBool.Request(data=bool(paused)),
                                 service_name=self.service_name, timeout_s=self.timeout_s,
                                 on_response=answered, on_failure=lambda reason: on_done(False, reason))
