"""``ros2py node|service|param`` against a live node with a SetBool service and parameters."""

from __future__ import annotations

import pytest
import yaml

from tests.helpers.ros_cli import DISCOVERY, run_cli

pytestmark = pytest.mark.ros


@pytest.fixture
def server(spinning):
    """Node /cli_server: a SetBool service recording requests, parameters with a set-callback."""
    from rcl_interfaces.msg import SetParametersResult
    from std_msgs.msg import String
    from std_srvs.srv import SetBool

    node = spinning("cli_server")
    node.requests = []
    node.parameter_updates = []

    def set_flag(request, response):
        node.requests.append(request.data)
        response.success = request.data
        response.message = "flag is on" if request.data else "flag is off"
        return response

    def on_set(parameters):
        node.parameter_updates.extend((p.name, p.value) for p in parameters)
        if any(p.name == "max_speed" and p.value < 0.0 for p in parameters):
            return SetParametersResult(successful=False, reason="max_speed must be >= 0")
        return SetParametersResult(successful=True)

    node.create_service(SetBool, "cli_set_flag", set_flag)
    node.create_publisher(String, "cli_status", 10)
    node.declare_parameter("max_speed", 0.5)
    node.declare_parameter("controller.gain", 3)
    node.declare_parameter("frames", ["map", "odom"])
    node.add_on_set_parameters_callback(on_set)
    return node


def test_node_list_and_info_show_the_node_and_its_endpoints(server):
    listed = run_cli("node", "list", *DISCOVERY)
    assert listed.code == 0, listed.output
    assert "/cli_server" in listed.lines
    assert not any(line.startswith("/_ros2py") for line in listed.lines)  # the CLI's own node is hidden

    info = run_cli("node", "info", "/cli_server", *DISCOVERY)
    assert info.code == 0, info.output
    lines = info.lines
    assert lines[0] == "/cli_server"
    sections = [line.strip() for line in lines if not line.startswith("    ")][1:]
    assert sections == ["Subscribers:", "Publishers:", "Service Servers:", "Service Clients:",
                        "Action Servers:", "Action Clients:"]
    publishers = lines[lines.index("  Publishers:") + 1:lines.index("  Service Servers:")]
    assert "    /cli_status: std_msgs/msg/String" in publishers
    assert "    /cli_set_flag: std_srvs/srv/SetBool" in lines


def test_service_list_and_call_reach_the_server(server):
    listed = run_cli("service", "list", "-t", *DISCOVERY)
    assert listed.code == 0, listed.output
    assert "/cli_set_flag [std_srvs/srv/SetBool]" in listed.lines

    called = run_cli("service", "call", "/cli_set_flag", "std_srvs/srv/SetBool", "{data: true}", *DISCOVERY)
    assert called.code == 0, called.output
    assert called.lines == [
        "requester: making request: std_srvs.srv.SetBool_Request(data=True)", "",
        "response:", "std_srvs.srv.SetBool_Response(success=True, message='flag is on')", "",
    ]
    assert server.requests == [True]


def test_service_call_without_type_resolves_it_from_the_graph(server):
    called = run_cli("service", "call", "cli_set_flag", "{data: false}", *DISCOVERY)
    assert called.code == 0, called.output
    assert "std_srvs.srv.SetBool_Response(success=False, message='flag is off')" in called.lines
    assert server.requests == [False]


def test_param_set_changes_the_live_parameter_and_the_callback_sees_it(server):
    result = run_cli("param", "set", "/cli_server", "max_speed", "0.8", *DISCOVERY)

    assert result.code == 0, result.output
    assert result.lines == ["Set parameter successful"]
    assert ("max_speed", 0.8) in server.parameter_updates
    assert server.get_parameter("max_speed").value == 0.8

    got = run_cli("param", "get", "cli_server", "max_speed", *DISCOVERY)
    assert got.lines == ["Double value is: 0.8"]


def test_param_set_rejected_by_the_node_is_one_line_and_exit_1(server):
    result = run_cli("param", "set", "/cli_server", "max_speed", "-1.0", *DISCOVERY)
    assert result.code == 1
    assert result.lines == ["Set parameter failed: max_speed must be >= 0"]
    assert server.get_parameter("max_speed").value == 0.5


def test_param_list_and_dump_give_every_parameter(server):
    listed = run_cli("param", "list", "/cli_server", *DISCOVERY)
    assert listed.code == 0, listed.output
    assert {"  max_speed", "  controller.gain", "  frames", "  use_sim_time"} <= set(listed.lines)

    dumped = run_cli("param", "dump", "/cli_server", *DISCOVERY)
    assert dumped.code == 0, dumped.output
    parameters = yaml.safe_load(dumped.output)["/cli_server"]["ros__parameters"]
    assert parameters["max_speed"] == 0.5
    assert parameters["controller"] == {"gain": 3}
    assert parameters["frames"] == ["map", "odom"]
    assert parameters["use_sim_time"] is False


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["param", "get", "/cli_no_node", "x", "--timeout", "1"],
         "Node not found: '/cli_no_node' (waited 1.0 s for it to appear)"),
        (["node", "info", "/cli_no_node", "--timeout", "1"],
         "Node not found: '/cli_no_node' (waited 1.0 s for it to appear)"),
        (["service", "call", "/cli_no_service", "std_srvs/srv/SetBool", "{data: true}", "--timeout", "1"],
         "timed out after 1.0 s waiting for service '/cli_no_service' to become available"),
        (["service", "call", "/cli_no_service", "std_srvs/srv/SetBool", "{data: 2}"],
         "std_srvs/srv/SetBool_Request.data: expected true or false, got 2"),
        (["service", "call", "/cli_no_service", "--timeout", "1"],
         "Unknown service '/cli_no_service' (waited 1.0 s for it to appear)"),
    ],
)
def test_user_errors_are_one_line_and_exit_code_1(args, message):
    result = run_cli(*args)
    assert result.code == 1
    assert result.lines == [message], result.output


def test_param_get_of_an_undeclared_parameter_fails(server):
    result = run_cli("param", "get", "/cli_server", "no_such_param", *DISCOVERY)
    assert result.code == 1
    assert result.lines == ["Parameter not set: 'no_such_param' on node '/cli_server'"]
