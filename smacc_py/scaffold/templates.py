'''The files ``smacc-new`` writes, as ``string.Template`` texts: ``$pkg`` is the package name
(``sm_my_machine``), ``$Sm`` the machine class (``SmMyMachine``).

The layout is that of SMACC2's reference machines (the machine, ``states/``, ``orthogonals/``,
``clients/<client>/client_behaviors/``), in Python packages; imports inside the package are relative, so
the package works wherever it is put and whatever it is renamed to. Lines stay within ruff's default
88 columns (with names up to about 20 characters), and imports are sorted as ruff sorts them outside
this repository (``smacc_py`` and the message packages are third-party there). Each file says what to
change to grow it.
'''

from __future__ import annotations

PACKAGE_INIT = '''"""$pkg: a SMACC2-style state machine on smacc_py.

Run it on the ROS graph, from the folder holding this package (Ctrl-C stops
it), and draw its graph from the declarations alone::

    smacc-run ./$pkg
    smacc-graph ./$pkg

Test it without ROS: ``python -m pytest $pkg/tests``.

Layout (SMACC2's reference machines): the machine module ``$pkg``,
``states/`` one module per state, ``orthogonals/`` one per orthogonal,
``clients/cl_heartbeat/`` a client and its ``client_behaviors/``, ``tests/``.
"""

from .$pkg import $Sm

STATE_MACHINE = $Sm

__all__ = ["STATE_MACHINE", "$Sm"]
'''

MACHINE = '''"""$Sm: StState1 publishes a few heartbeats, then starts over.

SMACC2: ``SmaccStateMachineBase<$Sm, StState1>``, whose ``onInitialize``
creates the orthogonals. States name this class by name (``parent="$Sm"``),
so they need not import this module. To add a state, write its module under
``states/`` and import it here, or from a state that transitions to it.
"""

from __future__ import annotations

from smacc_py.core import SmaccStateMachineBase

from .orthogonals.or_heartbeat import OrHeartbeat
from .states.st_state_1 import StState1


class $Sm(SmaccStateMachineBase):
    """Beats on OrHeartbeat in StState1, forever."""

    initial_state = StState1

    def on_initialize(self) -> None:
        self.create_orthogonal(OrHeartbeat)
'''

STATES_INIT = '''"""The states of $Sm, one module each (SMACC2: ``states/``)."""

from .st_state_1 import StState1

__all__ = ["StState1"]
'''

STATE_1 = '''"""StState1: three heartbeats on OrHeartbeat (CbBeat), then again.

SMACC2: ``SmaccState<StState1, $Sm>`` with the reaction
``Transition<EvCbSuccess<CbBeat, OrHeartbeat>, StState1, SUCCESS>`` and, in
``staticConfigure``, ``configure_orthogonal<OrHeartbeat, CbBeat>(3, 0.5)``.

A transition names its target by class or by name ("StState1"), so states may
refer to each other in any order and from any module.
"""

from __future__ import annotations

from smacc_py.core import SUCCESS, EvCbSuccess, SmaccState, Transition

from ..clients.cl_heartbeat import CbBeat
from ..orthogonals.or_heartbeat import OrHeartbeat

BEATS = 3  # heartbeats per visit
PERIOD_S = 0.5  # s of node clock between two heartbeats


class StState1(SmaccState, parent="$Sm"):
    """Beat BEATS times, one every PERIOD_S, then start over."""

    reactions = (
        Transition(EvCbSuccess[CbBeat, OrHeartbeat], "StState1", SUCCESS),
    )

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrHeartbeat, CbBeat, BEATS, PERIOD_S)

    def on_entry(self) -> None:
        self.get_logger().info("StState1: beating")
'''

ORTHOGONALS_INIT = '''"""The orthogonals of $Sm, one module each (SMACC2: ``orthogonals/``)."""

from .or_heartbeat import OrHeartbeat

__all__ = ["OrHeartbeat"]
'''

OR_HEARTBEAT = '''"""OrHeartbeat: the orthogonal holding ClHeartbeat.

SMACC2: ``Orthogonal<OrHeartbeat>`` calling ``createClient<ClHeartbeat>()``.
"""

from __future__ import annotations

from smacc_py.core import Orthogonal

from ..clients.cl_heartbeat import ClHeartbeat


class OrHeartbeat(Orthogonal):
    """Heartbeats on ``~/heartbeat`` (in the node's namespace)."""

    def on_initialize(self) -> None:
        self.create_client(ClHeartbeat, "~/heartbeat")
'''

CLIENTS_INIT = '''"""The clients of $Sm (SMACC2: ``clients/``)."""
'''

CLIENT_INIT = '''"""cl_heartbeat: ClHeartbeat and its behavior CbBeat."""

from .cl_heartbeat import ClHeartbeat
from .client_behaviors.cb_beat import CbBeat

__all__ = ["CbBeat", "ClHeartbeat"]
'''

CLIENT = '''"""ClHeartbeat: publishes std_msgs/String heartbeats.

A client lives as long as the machine and is its proxy to something outside
(a topic, a service, an action server); behaviors ask it to act. This one is a
SmaccPublisherClient: its publisher exists from the machine's start, so
subscribers are matched before the first beat. For your own client, subclass
a base of ``smacc_py.clients`` (SmaccSubscriberClient, SmaccServiceClient,
SmaccActionClientBase ...) or ``smacc_py.core.ISmaccClient``.
"""

from __future__ import annotations

from smacc_py.clients import SmaccPublisherClient
from std_msgs.msg import String


class ClHeartbeat(SmaccPublisherClient):
    """Publishes numbered heartbeats on ``topic``."""

    def __init__(self, topic: str = "~/heartbeat") -> None:
        super().__init__(String, topic)
        self.beats = 0

    def beat(self, text: str) -> None:
        """Publish one heartbeat."""
        self.beats += 1
        self.publish(String(data=text))
'''

BEHAVIORS_INIT = '''"""The client behaviors of ClHeartbeat."""
'''

CB_BEAT = '''"""CbBeat: a few heartbeats, one per period of node clock, then EvCbSuccess.

A client behavior lives as long as its state. This one is updatable (SMACC2's
ISmaccUpdatable): the runtime calls ``update()`` at most once per update
period, on the node clock, so sim time works. Its success event is
``EvCbSuccess[CbBeat, OrHeartbeat]`` (``EvCbSuccess<CbBeat, OrHeartbeat>``).
"""

from __future__ import annotations

from smacc_py.core import ISmaccUpdatable, SmaccClientBehavior

from ..cl_heartbeat import ClHeartbeat


class CbBeat(SmaccClientBehavior, ISmaccUpdatable):
    """``beats`` heartbeats, one per ``period_s`` (s), then post success."""

    def __init__(self, beats: int = 3, period_s: float = 0.5) -> None:
        self.beats = beats
        self.sent = 0
        self.set_update_period(period_s)

    def on_entry(self) -> None:
        self.client = self.requires_client(ClHeartbeat)

    def update(self) -> None:
        if self.sent >= self.beats:
            return
        self.sent += 1
        self.client.beat(f"beat {self.sent}/{self.beats}")
        if self.sent == self.beats:
            self.get_logger().info(f"CbBeat: {self.beats} beats sent")
            self.post_success_event()
'''

TESTS_INIT = '''"""Tests of $Sm."""
'''

TEST_MACHINE = '''"""$Sm on smacc_py.testing's stand-ins: no ROS graph, a manual clock.

The machine's own states, orthogonals and behaviors run; only the ROS ends
(the publisher) are replaced. Run: ``python -m pytest $pkg/tests``.
"""

from __future__ import annotations

from smacc_py.testing import MachineHarness

from .. import $Sm


def test_state_1_beats_three_times_then_starts_over() -> None:
    with MachineHarness($Sm) as harness:
        loops = harness.transitions
        assert harness.drive(lambda: len(loops()) >= 2, max_sim_s=10.0)
        assert loops()[:2] == [("StState1", "StState1", "SUCCESS")] * 2
        beats = [msg.data for msg in harness.published("~/heartbeat")]
        assert beats[:4] == ["beat 1/3", "beat 2/3", "beat 3/3", "beat 1/3"]
'''

#: Relative path (``$pkg`` substituted) → template.
FILES: dict[str, str] = {
    "__init__.py": PACKAGE_INIT,
    "$pkg.py": MACHINE,
    "states/__init__.py": STATES_INIT,
    "states/st_state_1.py": STATE_1,
    "orthogonals/__init__.py": ORTHOGONALS_INIT,
    "orthogonals/or_heartbeat.py": OR_HEARTBEAT,
    "clients/__init__.py": CLIENTS_INIT,
    "clients/cl_heartbeat/__init__.py": CLIENT_INIT,
    "clients/cl_heartbeat/cl_heartbeat.py": CLIENT,
    "clients/cl_heartbeat/client_behaviors/__init__.py": BEHAVIORS_INIT,
    "clients/cl_heartbeat/client_behaviors/cb_beat.py": CB_BEAT,
    "tests/__init__.py": TESTS_INIT,
    "tests/test_$pkg.py": TEST_MACHINE,
}
