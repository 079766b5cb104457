"""A live browser viewer for the ROS graph: RViz's map view, SMACC2's RTA and Groot's monitor in one page.

``navsuite-viewer`` (``python -m navsuite_tools.viewer.main``) starts one rclpy node and a stdlib HTTP
server on loopback. The node keeps the latest value of every layer it finds on the graph (map, costmaps, scan,
poses, particles, plans, goals, battery, SMACC2 introspection, Nav2 behavior tree log); the server
streams changed layers to each browser over Server-Sent Events at most ``rate`` times a second and
takes "2D Pose Estimate" / "Nav2 Goal" clicks as POSTs. The page (``static/``) is plain JS with no
external resources, so it works with no account and no internet.

Modules: ``hub`` (latest-value store, versions, throttling), ``encode`` (numbers → JSON payloads),
``layers`` (which topics, and message → payload), ``monitors`` (state machine graph layout and
behavior tree status, pure), ``node`` (ROS side), ``server`` (HTTP side), ``main`` (command line).
"""
