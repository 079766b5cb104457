"""Run reports: one PNG that shows what happened in a recorded run.

:func:`write_report` reads an MCAP recording (:mod:`navsuite_tools.bag`) and draws the map, the
ground-truth and AMCL trajectories, global plans, goals, collisions, the state-machine timeline
and the localization error over time. It only reads topics and message types (sim2d's
``ground_truth`` and ``sim2d/collisions``, Nav2's ``/map``, ``/amcl_pose``, ``/plan``,
``/goal_pose``, SMACC2's ``/<Sm>/smacc/transition_log``); it never imports the packages that
publish them. Missing topics leave their panel with a note instead of failing.
"""

from navsuite_tools.report.render import ReportParams, write_report

__all__ = ["ReportParams", "write_report"]
