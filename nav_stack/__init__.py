"""nav_stack: a Nav2-style navigation stack in Python.

``nav_stack.core`` holds the algorithms (numpy: grids, map I/O, costmaps, localization, planning,
control, behaviors, behavior trees) with no ROS; ``nav_stack.ros`` wraps them in lifecycle nodes
whose names, topics, QoS, parameters and error codes follow Nav2 Jazzy.
"""
