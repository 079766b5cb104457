"""What the states of sm_three_some share: the countdown and the behaviors each configures, and the log
lines of their entry and exit."""

from __future__ import annotations

from smacc_py.clients.cl_keyboard import CbDefaultKeyboardBehavior
from smacc_py.clients.cl_ros_timer import CbTimerCountdownOnce
from smacc_py.core import SmaccState
from smacc_py.state_machines.sm_three_some.clients.cl_subscriber import CbWatchdogSubscriberBehavior
from smacc_py.state_machines.sm_three_some.orthogonals import OrKeyboard, OrSubscriber, OrTimer

COUNTDOWN_TICKS = 10  # CbTimerCountdownOnce(10): 10 ticks of 0.5 s


class LoggedState(SmaccState):
    """Logs "On Entry!" and "On Exit!", as every upstream state does."""

    def on_entry(self) -> None:
        self.getLogger().info(f"{type(self).__name__}: On Entry!")

    def on_exit(self) -> None:
        self.getLogger().info(f"{type(self).__name__}: On Exit!")


def configure_timeout_keys_and_sensor(state: type[SmaccState]) -> None:
    """The ``staticConfigure`` of most upstream states: the countdown, the subscriber's watchdog
    behavior and the keyboard behavior (call it from ``static_configure``)."""
    state.configure_orthogonal(OrTimer, CbTimerCountdownOnce, COUNTDOWN_TICKS)
    state.configure_orthogonal(OrSubscriber, CbWatchdogSubscriberBehavior)
    state.configure_orthogonal(OrKeyboard, CbDefaultKeyboardBehavior)
