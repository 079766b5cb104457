"""The ``ros2py`` command: one module per verb group (topic, node, service, action, param,
interface), wired together by :mod:`ros_tools.cli.main`; shared waits and options in
:mod:`ros_tools.cli.common`."""
