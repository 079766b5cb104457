"""docking_server (opennav_docking): the server, its dock plugins, its navigator client
and the dock database read from the world.
"""
