"""collision_monitor: the node, its data sources and its polygon markers.
"""
