"""behavior_server: spin, back up, drive on heading, wait, assisted teleop.
"""
