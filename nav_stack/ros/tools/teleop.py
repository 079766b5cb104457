"""nav-teleop: keyboard teleoperation, as turtlebot3_teleop's teleop_keyboard (used to drive SLAM runs).

Keys (turtlebot3_teleop's):  w / x  linear velocity +/- 0.01 m/s,  a / d  angular velocity +/- 0.1 rad/s,
s or space  stop,  q or Ctrl-C  quit. Targets are clamped to the model's limits (waffle 0.26 m/s,
1.82 rad/s; burger 0.22 m/s, 2.84 rad/s; tb4 0.306 m/s, 1.90 rad/s). The current command is re-published every
``--period`` (0.1 s) so the simulator's cmd_vel watchdog (0.5 s) never brakes a robot being driven.

Interactive mode puts the terminal in raw mode (restored on exit). ``--keys wwwad`` replays keys
instead, one per period, then publishes a stop and exits (for tests and scripts; it first waits up to
SUBSCRIBER_WAIT for a cmd_vel subscriber, since messages sent before discovery are lost, and on exit up
to ACK_WAIT for its last commands to be acknowledged).
``cmd_vel`` is Twist, or TwistStamped with ``-p enable_stamped_cmd_vel:=true`` (Nav2's name); unset,
it is the type the robot's subscription takes (nav-bringup's simulator takes TwistStamped in lockstep).
"""

from __future__ import annotations

import argparse
import contextlib
import select
import sys
import termios
import time
import tty
from collections.abc import Callable, Iterator
from dataclasses import dataclass

from ros_tools.runtime.executor import add_executor_argument

LINEAR_STEP = 0.01  # m/s per key press (turtlebot3_teleop LIN_VEL_STEP_SIZE)
ANGULAR_STEP = 0.1  # rad/s per key press (ANG_VEL_STEP_SIZE)
# m/s, rad/s: ROBOTIS' TurtleBot3 specs; tb4: the Create 3's safe-mode speed and the TB4 manual's turn rate
LIMITS = {"waffle": (0.26, 1.82), "waffle_pi": (0.26, 1.82), "burger": (0.22, 2.84), "tb4": (0.306, 1.90)}
QUIT_KEYS = ("q", "\x03")
SUBSCRIBER_WAIT = 10.0  # wall s --keys waits for a cmd_vel subscriber before replaying
#: wall s the exit waits for the subscribers to acknowledge the last commands (the stop among them):
#: a reliable message still unacknowledged when the process ends is lost, and the robot drives on
#: (a subscriber that has not matched this publisher yet asks for it once it has). Fast DDS collects
#: the acknowledgements at its heartbeat period, so the exit usually takes the whole wait.
ACK_WAIT = 2.0
HELP = """Control your TurtleBot3!
---------------------------
        w
   a    s    d
        x
w/x : increase/decrease linear velocity  (+/- 0.01 m/s)
a/d : increase/decrease angular velocity (+/- 0.1 rad/s)
s, space : stop        q, Ctrl-C : quit"""


@dataclass
class TeleopState:
    """Target velocities changed by keys, clamped to ``max_linear`` (m/s) and ``max_angular`` (rad/s)."""

    max_linear: float
    max_angular: float
    linear: float = 0.0
    angular: float = 0.0

    def press(self, key: str) -> bool:
        """Apply one key; False when the key means nothing (the command is unchanged)."""
        if key == "w":
            self.linear += LINEAR_STEP
        elif key == "x":
            self.linear -= LINEAR_STEP
        elif key == "a":
            self.angular += ANGULAR_STEP
        elif key == "d":
            self.angular -= ANGULAR_STEP
        elif key in ("s", " "):
            self.linear = self.angular = 0.0
        else:
            return False
        # Round to the step grid so 30 presses give exactly 0.30 (float drift would show in the status).
        self.linear = round(max(-self.max_linear, min(self.max_linear, self.linear)), 3)
        self.angular = round(max(-self.max_angular, min(self.max_angular, self.angular)), 3)
        return True


@contextlib.contextmanager
def raw_terminal() -> Iterator[None]:
    """Single-key reads without echo; the terminal settings come back however the block ends."""
    fd = sys.stdin.fileno()
    saved = termios.tcgetattr(fd)
    try:
        tty.setraw(fd)
        yield
    finally:
        termios.tcsetattr(fd, termios.TCSADRAIN, saved)


def read_key(timeout: float) -> str:
    """One key from stdin, or '' after ``timeout`` seconds."""
    ready, _, _ = select.select([sys.stdin], [], [], timeout)
    return sys.stdin.read(1) if ready else ""


def parse_args(argv: list[str]) -> argparse.Namespace:
    parser = argparse.ArgumentParser(prog="nav-teleop", description=HELP,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--model", choices=sorted(LIMITS), default="waffle",
                        help="speed limits of this TurtleBot")
    parser.add_argument("--keys", help="replay these keys (one per period), stop, and exit")
    parser.add_argument("--period", type=float, default=0.1, help="publish period (s, wall clock)")
    add_executor_argument(parser)
    return parser.parse_args(argv)


def main(argv: list[str] | None = None) -> int:
    """Entry point of ``nav-teleop``; ROS arguments after ``--ros-args``.

    The process shape is the shared runner's (ros_tools.runtime.runner.ros_process): rclpy's signal
    handler off, SIGTERM (and Ctrl-C outside raw mode) only raise a flag, so the last stop is always
    published and acknowledged while the context is still up. The main loop is the key reader's, not
    a spin-until-done loop: a key is published the moment it is read.
    """
    from rclpy.duration import Duration
    from rclpy.node import Node
    from rclpy.parameter import Parameter

    from ros_tools.cmd_vel import CmdVelPublisher
    from ros_tools.runtime.runner import ros_process

    args_in = list(sys.argv[1:] if argv is None else argv)
    split = args_in.index("--ros-args") if "--ros-args" in args_in else len(args_in)
    args = parse_args(args_in[:split])
    if args.keys is not None and (bad := sorted(set(args.keys) - set("wxads "))):
        print(f"nav-teleop: error: --keys: unknown keys {bad} (use w x a d s and space)", file=sys.stderr)
        return 2
    with ros_process(["nav-teleop", *args_in[split:]]) as process:
        node = Node("teleop_keyboard")
        executor = process.executor(args.executor)
        executor.add_node(node)
        # Unset: follow the type the robot's cmd_vel subscription takes (CmdVelPublisher with None).
        stamped = node.declare_parameter("enable_stamped_cmd_vel", Parameter.Type.BOOL).value
        cmd = CmdVelPublisher(node, None if stamped is None else bool(stamped))
        state = TeleopState(*LIMITS[args.model])

        def pause() -> None:
            """Serve the node for one period (the main loop's pacing; no callback waits)."""
            deadline = time.monotonic() + args.period
            while (left := deadline - time.monotonic()) > 0:
                executor.spin_once(timeout_sec=left)

        try:
            if args.keys is not None:
                deadline = time.monotonic() + SUBSCRIBER_WAIT
                while (cmd.publisher.get_subscription_count() == 0 and time.monotonic() < deadline
                       and process.ok()):
                    pause()  # a replay sent before discovery is lost
                    cmd.follow_subscribers()  # the robot's type, once the graph shows its subscription
                if cmd.publisher.get_subscription_count() == 0 and process.ok():
                    print(f"nav-teleop: no cmd_vel subscriber after {SUBSCRIBER_WAIT:.0f} s; replaying "
                          "anyway (is the simulator running, on this ROS_DOMAIN_ID?)", file=sys.stderr)
                for key in args.keys:
                    if not process.ok():
                        break
                    state.press(key)
                    cmd.publish(state.linear, state.angular)
                    pause()
            else:
                _interactive(cmd, state, args.period, process.ok)
        finally:
            cmd.stop()
            pause()  # let the stop leave before the node goes
            cmd.publisher.wait_for_all_acked(Duration(seconds=ACK_WAIT))
            executor.shutdown()
            node.destroy_node()
    return 0


def _interactive(cmd: object, state: TeleopState, period: float, running: Callable[[], bool]) -> None:
    """Read keys until a quit key, or until ``running()`` turns false (SIGTERM)."""
    print(HELP)
    with raw_terminal():
        while running():
            key = read_key(period)
            if key in QUIT_KEYS:
                return
            if state.press(key):
                status = f"linear {state.linear:+.2f} m/s  angular {state.angular:+.2f} rad/s"
                sys.stdout.write(f"\rcurrently: {status} ")
                sys.stdout.flush()
            cmd.publish(state.linear, state.angular)  # type: ignore[attr-defined]


if __name__ == "__main__":
    sys.exit(main())
