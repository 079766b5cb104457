"""Scenario farm: many short missions, each isolated on its own ROS domain, judged by pass criteria.

Layers, bottom-up (only ``injector`` and ``goal_driver`` use rclpy, in their own processes):

* ``schema`` — the scenario file: frozen dataclasses and their validation (pure);
* ``verdict`` — what a run measured (``Outcome``) judged against ``Expect`` (pure);
* ``outcome`` — an ``Outcome`` read from a mission command's console lines (pure);
* ``commands`` — the command lines and parameter overlays that run one scenario (pure);
* ``metrics`` — collisions and localization error from the run's MCAP recording;
* ``injector``, ``goal_driver`` — rclpy processes: events (kidnap, lidar dropout, dropped obstacle,
  killing the navigation process, with ``navigation_kill``) at sim times, a goal list;
* ``worker`` — runs one scenario in its own processes and writes ``result.json``;
* ``domains`` — ROS_DOMAIN_ID claims shared with test sessions and benchmarks;
* ``executor`` — the backend seam, one job's run (``run_job``) and the local process pool;
* ``cluster`` — the Ray backend: each job a Ray task on a cluster node, artifacts shipped back;
* ``farm`` — submits, waits, judges (shared by the command and the plugin);
* ``table``, ``summary`` — the live console table, summary HTML and JUnit XML;
* ``main`` — ``navsuite-scenarios``; ``pytest_plugin`` — ``pytest --scenarios FILE``.
"""
