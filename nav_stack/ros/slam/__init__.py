"""Mapping: the SLAM node (slam_toolbox's interface), its inputs and services, its bringup,
the map saver and frontier exploration.
"""
