"""CbPauseSlam and CbResumeSlam: stop and restart the SLAM node's mapping of new scans through CpSlamToolbox.

SMACC2's versions call slam_toolbox's toggling Pause service only when CpSlamToolbox believes the
node is in the other state. Here the request names the wanted state (see cp_slam_toolbox), so it
is always sent: a node paused or resumed by someone else still ends up as the behavior says.
Success posts ``EvCbSuccess[Cb, Or](state=..., message=...)``; a refusal, or no answer within
CpSlamToolbox's ``timeout_s``, posts ``EvCbFailure[Cb, Or](reason=...)``. A call still pending when the
state exits is abandoned.
"""

from __future__ import annotations

from typing import ClassVar

from smacc_py.clients.cl_nav2z.cp_slam_toolbox import CpSlamToolbox
from smacc_py.core import SmaccClientBehavior
from smacc_py.ros.components.service_call import ServiceCall


class _CbSetSlamPaused(SmaccClientBehavior):
    """Sends one pause (``paused`` True) or resume request on entry."""

    paused: ClassVar[bool]
    call: ServiceCall | None = None

    def on_entry(self) -> None:
        self._slam = self.requires_component(CpSlamToolbox)
        self.call = self._slam.set_paused(self.paused, self._on_done)

    def _on_done(self, succeeded: bool, detail: str) -> None:
        if succeeded:
            self.post_success_event(state=self._slam.state, message=detail)
        else:
            self.post_failure_event(reason=f"{type(self).__name__}: {detail}")

    def on_exit(self) -> None:
        if self.call is not None and not self.call.done:
            self.call.abandon()


class CbPauseSlam(_CbSetSlamPaused):
    """Pause SLAM: the node ignores scans until resumed; its map and map → odom stay published."""

    paused = True


class CbResumeSlam(_CbSetSlamPaused):
    """Resume SLAM: the node integrates scans again."""

    paused = False
