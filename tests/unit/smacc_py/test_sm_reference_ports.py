"""The ports of sm_atomic_24hr, sm_three_some and sm_atomic_services on the manual clock (no ROS graph):
what the system tests cannot reach cheaply (a full day's pace, the recovery mode nobody enters on the
graph, the service machine without DDS). Upstream files are named in each test."""

from __future__ import annotations

from typing import Any

from std_srvs.srv import Empty

from smacc_py.state_machines.sm_atomic_24hr import NOMINAL_TRANSITIONS as ATOMIC_24HR
from smacc_py.state_machines.sm_atomic_24hr import STATE_SECONDS, SmAtomic24Hr
from smacc_py.state_machines.sm_atomic_services import NOMINAL_TRANSITIONS as SERVICES
from smacc_py.state_machines.sm_atomic_services import SmAtomicServices
from smacc_py.state_machines.sm_atomic_services.clients import ClServiceClient, ClServiceServer
from smacc_py.state_machines.sm_three_some import NOMINAL_TRANSITIONS as THREE_SOME
from smacc_py.state_machines.sm_three_some import EvFail, EvToDeep, SmThreeSome
from smacc_py.testing import MachineHarness


def test_sm_atomic_24hr_changes_state_every_500_ticks() -> None:
    # sm_atomic_24hr/states/st_state_{1,2}.hpp: CbTimerCountdownOnce(500) on a 1 s ClRosTimer
    with MachineHarness(SmAtomic24Hr, step_s=0.5) as harness:
        harness.advance(4 * STATE_SECONDS + 1.0)
        assert tuple(harness.transitions()) == ATOMIC_24HR
        assert [record.stamp_s for record in harness.sm.transition_log] == [500.0, 1000.0, 1500.0, 2000.0]


def test_sm_three_some_without_input_ends_in_state_4() -> None:
    with MachineHarness(SmThreeSome) as harness:
        harness.advance(130.0)
        assert tuple(harness.transitions()) == THREE_SOME
        assert harness.sm.current_state_names() == ["MsRun", "StState4"]
        assert harness.sm.transition_log[-1].stamp_s == 115.0  # 23 countdowns of 10 ticks of 0.5 s


def test_sm_three_some_recovers_into_the_deep_history_of_the_run_mode() -> None:
    # mode_states/ms_recover.hpp: EvToDeep -> deep_history<MsRun::LastDeepState>; st_state_1.hpp: EvFail
    with MachineHarness(SmThreeSome) as harness:
        harness.press("n")  # EvKeyPressN and the sensor's EvTopicMessage: StState1 leaves once
        harness.press("n")
        assert harness.sm.current_state_names() == ["MsRun", "StState3"]
        harness.sm.post_event(EvFail)  # only StState1 reacts to it
        harness.sm.process_events()
        assert harness.sm.current_state_names() == ["MsRun", "StState3"]
        harness.press("p")
        harness.press("p")
        harness.sm.post_event(EvFail)
        harness.sm.process_events()
        assert harness.sm.current_state_names() == ["MsRecover"]
        harness.sm.post_event(EvToDeep)
        harness.sm.process_events()
        assert harness.sm.current_state_names() == ["MsRun", "StState1"]
        assert harness.transitions()[-2:] == [("StState1", "MsRecover", "ABORT"),
                                              ("MsRecover", "MsRun", "SUCCESS")]


def test_sm_three_some_key_p_in_state_1_enters_the_first_superstate() -> None:
    with MachineHarness(SmThreeSome) as harness:
        harness.press("p")
        assert harness.transitions()[:2] == [("StState1", "Ss1", "PREVIOUS"),
                                            ("Ss1StiState1", "Ss1StiState2", "CONTINUELOOP")]


class _NoServer(ClServiceServer):
    def on_initialize(self) -> None:
        pass


class _NoClient(ClServiceClient):
    def on_initialize(self) -> None:
        pass


def test_sm_atomic_services_waits_in_state_2_for_a_request() -> None:
    # sm_atomic_services/states/st_state_2.hpp: EvServiceRequestReceieved<CbServiceServer, OrServices>
    substitutes: dict[type, Any] = {ClServiceServer: _NoServer, ClServiceClient: _NoClient}
    with MachineHarness(SmAtomicServices, substitutes=substitutes) as harness:
        server = harness.sm.requires_client(ClServiceServer)
        server.on_request(Empty.Request(), Empty.Response())  # in State1: nobody listens
        harness.sm.process_events()
        harness.advance(60.0)
        assert harness.transitions() == [SERVICES[0]]
        server.on_request(Empty.Request(), Empty.Response())
        harness.sm.process_events()
        harness.advance(5.5)
        server.on_request(Empty.Request(), Empty.Response())
        harness.sm.process_events()
        assert tuple(harness.transitions()) == SERVICES
        assert len(server.request_received) == 0  # back in State1: State2's behavior disconnected
