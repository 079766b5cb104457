"""smacc_py: a Python re-implementation of SMACC2, the event-driven state-machine library for ROS 2.

Layers (dependencies point downward only)::

    state_machines   reference machines (sm_nav2_test_1 ...), one folder each
    clients          client libraries (cl_nav2z, cl_ros2_timer, cl_keyboard ...)
    ros              rclpy runtime: node, SignalDetector polling, smacc2_msgs introspection
    core             the engine, stdlib only: events, states, orthogonals, clients, behaviors,
                     reactors, generators, validation, introspection, graph export

The public engine API lives in ``smacc_py.core``; names follow SMACC2 in snake_case
(``SmaccStateMachineBase``, ``configure_orthogonal``, ``requires_client``, ``EvCbSuccess[CbX, OrY]``),
so SMACC2 tutorials map one-to-one.
"""
