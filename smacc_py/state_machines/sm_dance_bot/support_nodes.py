"""The devices sm_dance_bot talks to, which upstream's launch file starts next to the machine:
the LED server, the temperature sensor and service node 3 (SMACC2: led_action_server_node,
temperature_sensor_node, service_node_3.py), as three small nodes spun by one executor in one process.

* ``led_server``: std_srvs/SetBool on ``/led_control`` (upstream: an LEDControl action server); it
  keeps the LED's state and republishes it on ``/led_state`` (std_msgs/Bool, latched) at each change.
* ``temperature_sensor_node``: sensor_msgs/Temperature on ``/temperature`` every ``--period`` s of sim
  time: ``--celsius`` (25 °C), except ``--hot-celsius`` (45 °C) from ``--heat-start`` to ``--heat-end``
  s of sim time, a scripted overheating that drives the machine into its recovery mode and back
  (``--no-overheat``: never). Upstream publishes made-up readings the machine only logs.
* ``service_node_3``: std_srvs/SetBool on ``/service_node3``; it answers success and logs the request.

Every node runs on sim time (``use_sim_time``). Prints ``support nodes ready`` once all three exist.
Stops on SIGINT or SIGTERM.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from typing import Any

READY_LINE = "support nodes ready"
LED_STATE_TOPIC = "/led_state"


def parse_args(argv: Sequence[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(prog="sm_dance_bot.support_nodes", description=__doc__.splitlines()[0])
    parser.add_argument("--celsius", type=float, default=25.0, help="normal reading (°C)")
    parser.add_argument("--hot-celsius", type=float, default=45.0, help="reading while overheating (°C)")
    parser.add_argument("--heat-start", type=float, default=60.0, help="sim s at which overheating starts")
    parser.add_argument("--heat-end", type=float, default=66.0, help="sim s at which it ends")
    parser.add_argument("--no-overheat", action="store_true", help="never overheat")
    parser.add_argument("--period", type=float, default=0.2, help="s of sim time between readings")
    options = parser.parse_args(argv)
    if not options.period > 0.0:
        parser.error(f"--period must be > 0 s, got {options.period}")
    if options.heat_end < options.heat_start:
        parser.error(f"--heat-end ({options.heat_end}) is before --heat-start ({options.heat_start})")
    return options


def reading_at(options: argparse.Namespace, sim_s: float) -> float:
    """The temperature (°C) at ``sim_s`` seconds of sim time."""
    hot = not options.no_overheat and options.heat_start <= sim_s < options.heat_end
    return float(options.hot_celsius if hot else options.celsius)


def make_nodes(options: argparse.Namespace, context: Any) -> list[Any]:
    """The three nodes (LED, temperature, service3) on ``context`` (None: rclpy's default context)."""
    from rclpy.node import Node
    from rclpy.parameter import Parameter
    from rclpy.qos import DurabilityPolicy, QoSProfile
    from sensor_msgs.msg import Temperature
    from std_msgs.msg import Bool
    from std_srvs.srv import SetBool

    sim_time = [Parameter("use_sim_time", value=True)]
    led = Node("led_server", context=context, parameter_overrides=sim_time)
    led_state = led.create_publisher(Bool, LED_STATE_TOPIC,
                                     QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))

    def on_led(request: SetBool.Request, response: SetBool.Response) -> SetBool.Response:
        led_state.publish(Bool(data=request.data))
        response.success, response.message = True, "LED on" if request.data else "LED off"
        return response

    led.create_service(SetBool, "/led_control", on_led)

    sensor = Node("temperature_sensor_node", context=context, parameter_overrides=sim_time)
    temperature = sensor.create_publisher(Temperature, "/temperature", 10)

    def publish_reading() -> None:
        now = sensor.get_clock().now()
        msg = Temperature(temperature=reading_at(options, now.nanoseconds * 1e-9), variance=0.0)
        msg.header.stamp = now.to_msg()
        msg.header.frame_id = "base_link"
        temperature.publish(msg)

    sensor.create_timer(options.period, publish_reading)

    service3 = Node("service_node_3", context=context, parameter_overrides=sim_time)

    def on_service3(request: SetBool.Request, response: SetBool.Response) -> SetBool.Response:
        service3.get_logger().info(f"service3 request: {request.data}")
        response.success, response.message = True, f"service3 {'on' if request.data else 'off'}"
        return response

    service3.create_service(SetBool, "/service_node3", on_service3)
    return [led, sensor, service3]


def main(argv: Sequence[str] | None = None) -> int:
    """Serve until SIGINT or SIGTERM (exit 0). Not a lockstep participant: the devices only answer."""
    from ros_tools.runtime.runner import run_nodes

    options = parse_args(argv)
    return run_nodes(lambda: make_nodes(options, None), role="support_nodes",
                     on_start=lambda executor, nodes: print(READY_LINE, flush=True), lockstep=False)


if __name__ == "__main__":
    sys.exit(main())
