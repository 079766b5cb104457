"""bt_navigator and what it uses besides its BT nodes (nav_stack.ros.bt_nodes): the
localization guard; the waypoint follower and the goal pose forwarder.
"""
