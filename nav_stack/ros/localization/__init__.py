"""Localization as Nav2's localization_launch starts it: map_server, amcl (with its health
and message helpers) and the initial pose publisher.
"""
