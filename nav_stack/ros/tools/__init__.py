"""Console tools for a running stack: nav-goal and the keyboard teleop.
"""
