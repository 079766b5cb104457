"""planner_server and smoother_server.
"""
