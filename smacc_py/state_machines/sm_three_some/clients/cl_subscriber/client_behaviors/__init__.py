"""ClSubscriber's behaviors (upstream's ``clients/cl_subscriber/client_behaviors/``)."""

from __future__ import annotations

from smacc_py.clients import CbDefaultMultiRoleSensorBehavior
from smacc_py.core import SmaccClientBehavior


class CbDefaultSubscriberBehavior(CbDefaultMultiRoleSensorBehavior):
    """Re-posts the sensor's messages as its own events while its state is active (no state uses it)."""

    def on_entry(self) -> None:
        super().on_entry()
        self.get_logger().info("[CbDefaultSubscriberBehavior] Behavior active")


class CbWatchdogSubscriberBehavior(SmaccClientBehavior):
    """Does nothing, as upstream's: the states configure it, the sensor client posts the events."""


__all__ = ["CbDefaultSubscriberBehavior", "CbWatchdogSubscriberBehavior"]
