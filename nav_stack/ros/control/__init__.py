"""controller_server with its controller plugins (RPP, DWB, MPPI, the rotation shim), the
robot-response watchdog, MPPI's trajectory markers and the velocity smoother.
"""
