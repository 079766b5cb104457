"""The ``ros2py`` command: one module per verb group (topic, node, service, action, param,
interface), wired together by :mod:`navsuite_tools.cli.main`; shared waits and options in
:mod:`navsuite_tools.cli.common`."""
