"""sm_dance_bot's own clients and behaviors (SMACC2: sm_dance_bot/clients/cl_*).

* ``ClLED`` + ``CbLEDOn`` / ``CbLEDOff``: SMACC2's cl_led drives an ``LEDControl`` action server; here the
  LED is a ``SmaccServiceClient`` of std_srvs/SetBool on ``/led_control`` (True: on), served by
  ``support_nodes.py``. The behaviors fire the request and return; the answer comes back as
  ``EvServiceResponse[ClLED, OrLED]``, which no state waits for (as upstream, where nothing waits for
  the LED goal either).
* ``ClLidarSensor`` + ``CbLidarSensor``: a ``ClMultiroleSensor`` on /scan (cl_lidar).
* ``ClTemperatureSensor`` + ``CbConditionTemperatureSensor``: a ``ClMultiroleSensor`` on /temperature
  (cl_temperature_sensor). The custom condition posts ``EvCustomTemperatureAlert`` when a reading rises
  above ``alert_celsius`` (40 °C, upstream's figure), once per crossing. ``CbTemperatureNormal`` (new,
  used by the recovery mode) succeeds on the first reading at or below ``normal_celsius``.
* ``ClStringPublisher`` + ``CbStringPublisher``: a ``ClRosPublisher`` of std_msgs/String; the behavior
  publishes its text when its state exits, as upstream's does.
* ``ClService3`` + ``CbService3``: a ``SmaccServiceClient`` of std_srvs/SetBool on /service_node3.
"""

from __future__ import annotations

import enum
from typing import Any

from sensor_msgs.msg import LaserScan, Temperature
from std_msgs.msg import String
from std_srvs.srv import SetBool

from smacc_py.clients import (
    CbDefaultMultiRoleSensorBehavior,
    ClMultiroleSensor,
    ClRosPublisher,
    SmaccServiceClient,
)
from smacc_py.core import SmaccClientBehavior, SmaccEvent

LED_SERVICE = "/led_control"
SERVICE3 = "/service_node3"
SCAN_TOPIC = "/scan"
TEMPERATURE_TOPIC = "/temperature"
STRING_PUBLISHER_TOPIC = "/string_publisher_out"
UPDATABLE_PUBLISHER_TOPIC = "/updatable_string_publisher_out"
SENSOR_TIMEOUT_S = 10.0  # s of machine clock without a message before EvTopicMessageTimeout (upstream's)
ALERT_CELSIUS = 40.0  # upstream's over-temperature threshold
NORMAL_CELSIUS = 38.0  # the recovery mode resumes at or below this (2 °C of hysteresis)


# --------------------------------------------------------------------------- LED (cl_led)
class ClLED(SmaccServiceClient):
    """The LED: SetBool on ``/led_control`` (SMACC2: ``cl_led::ClLED``, an LEDControl action client)."""

    def __init__(self, service_name: str = LED_SERVICE) -> None:
        super().__init__(SetBool, service_name)


class _CbLED(SmaccClientBehavior):
    on = True

    def on_entry(self) -> None:
        self.requires_client(ClLED).call(SetBool.Request(data=self.on))


class CbLEDOn(_CbLED):
    """Switch the LED on when the state is entered (SMACC2: ``cl_led::CbLEDOn``)."""


class CbLEDOff(_CbLED):
    """Switch the LED off when the state is entered (SMACC2: ``cl_led::CbLEDOff``)."""

    on = False


# --------------------------------------------------------------------------- lidar (cl_lidar)
class ClLidarSensor(ClMultiroleSensor):
    """LaserScan on /scan with a 10 s silence watchdog (SMACC2: ``cl_lidar::ClLidarSensor``)."""

    def __init__(self, topic: str = SCAN_TOPIC, timeout_s: float = SENSOR_TIMEOUT_S) -> None:
        super().__init__(LaserScan, topic, timeout_s=timeout_s)


class CbLidarSensor(CbDefaultMultiRoleSensorBehavior):
    """Re-posts the scans as ``EvTopicMessage[CbLidarSensor, OrObstaclePerception]`` while its state is active
    (SMACC2: ``cl_lidar::CbLidarSensor``)."""


# --------------------------------------------------------------------------- temperature
class EvCustomTemperatureAlert(SmaccEvent):
    """A reading rose above the alert threshold (payload ``celsius``); parameters (behavior, orthogonal).

    SMACC2: ``cl_temperature_sensor::EvCustomTemperatureAlert``.
    """


class ClTemperatureSensor(ClMultiroleSensor):
    """sensor_msgs/Temperature on /temperature, 10 s watchdog (SMACC2: ``ClTemperatureSensor``)."""

    def __init__(self, topic: str = TEMPERATURE_TOPIC, timeout_s: float = SENSOR_TIMEOUT_S) -> None:
        super().__init__(Temperature, topic, timeout_s=timeout_s)


class CbConditionTemperatureSensor(CbDefaultMultiRoleSensorBehavior):
    """The custom condition: ``EvCustomTemperatureAlert[CbConditionTemperatureSensor, Or]`` when a reading
    goes above ``alert_celsius`` (SMACC2: ``cl_temperature_sensor::CbConditionTemperatureSensor``, which
    posts on every hot reading; this one posts once per crossing, so a long hot spell is one alert)."""

    def __init__(self, alert_celsius: float = ALERT_CELSIUS) -> None:
        self.alert_celsius = alert_celsius
        self.hot = False

    def on_message_callback(self, msg: Any) -> None:
        hot = msg.temperature > self.alert_celsius
        if hot and not self.hot:
            self.post_event(self.own_event(EvCustomTemperatureAlert)(celsius=msg.temperature))
        self.hot = hot


class CbTemperatureNormal(SmaccClientBehavior):
    """Success on the first reading at or below ``normal_celsius`` while its state is active (new: the
    recovery mode's way back; upstream's recovery mode waits for another EvGlobalError)."""

    def __init__(self, normal_celsius: float = NORMAL_CELSIUS) -> None:
        self.normal_celsius = normal_celsius
        self._disconnect: Any = None

    def on_entry(self) -> None:
        self._disconnect = self.requires_client(ClTemperatureSensor).on_message_received(self._on_reading)

    def _on_reading(self, msg: Any) -> None:
        if msg.temperature <= self.normal_celsius and self._disconnect is not None:
            self._disconnect()
            self._disconnect = None
            self.post_success_event(celsius=msg.temperature)

    def on_exit(self) -> None:
        if self._disconnect is not None:
            self._disconnect()
            self._disconnect = None


# --------------------------------------------------------------------------- string publisher
class ClStringPublisher(ClRosPublisher):
    """std_msgs/String publisher (SMACC2: ``cl_string_publisher::ClStringPublisher``)."""

    def __init__(self, topic: str = STRING_PUBLISHER_TOPIC) -> None:
        super().__init__(String, topic)


class CbStringPublisher(SmaccClientBehavior):
    """Publishes ``text`` when its state exits (SMACC2: ``cl_string_publisher::CbStringPublisher``)."""

    def __init__(self, text: str) -> None:
        self.text = text

    def on_entry(self) -> None:
        self.client = self.requires_client(ClStringPublisher)

    def on_exit(self) -> None:
        self.client.publish(String(data=self.text))


# --------------------------------------------------------------------------- service3
class Service3Command(enum.Enum):
    """What CbService3 asks for (SMACC2: ``cl_service3::Service3Command``)."""

    SERVICE3_ON = True
    SERVICE3_OFF = False


class ClService3(SmaccServiceClient):
    """SetBool client of ``/service_node3`` (SMACC2: ``cl_service3::ClService3``)."""

    def __init__(self, service_name: str = SERVICE3) -> None:
        super().__init__(SetBool, service_name)


class CbService3(SmaccClientBehavior):
    """Sends ``SetBool(command.value)`` on entry (SMACC2: ``cl_service3::CbService3``); the answer is
    posted by the client as ``EvServiceResponse[ClService3, OrService3]``."""

    def __init__(self, command: Service3Command) -> None:
        self.command = command

    def on_entry(self) -> None:
        self.requires_client(ClService3).call(SetBool.Request(data=self.command.value))
