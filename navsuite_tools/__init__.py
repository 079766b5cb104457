"""navsuite_tools: the tools that sit above the stacks, for their users.

* ``scenarios``: the scenario farm (``navsuite-scenarios``, ``pytest --scenarios``), locally or on Ray;
* ``viewer``: the live web viewer (``navsuite-viewer``);
* ``bag`` and ``report``: MCAP recording and playback (``navsuite-bag``) and run reports;
* ``cli``: the ``ros2py`` command, what ``ros2`` gives a ROS installation.

They use the runtime layer, ros_tools, and never import sim2d, nav_stack or smacc_py: the farm runs
stacks by their commands, the others read the ROS graph or a recording. Nothing below them imports
them (import contracts in pyproject.toml), except the demos, which record and report their runs.
"""
