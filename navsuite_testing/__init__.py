"""What the tests and the benchmarks share: fakes, rigs and waits, grouped by subject.

Why a package of its own, beside tests/ and bench/ rather than inside tests/helpers: a benchmark
measures the same rigs the tests check (the slam node fed by the fake robot, the localization tour,
the SLAM exploration stack), and a benchmark that imported ``tests`` would depend on test modules
and on pytest's collection layout. Both now import this package, and neither imports the other's
modules; import-linter holds it so (pyproject.toml: bench never imports tests, the product packages
never import navsuite_testing). Fakes used by tests alone stay in tests/helpers.

It is not part of the product: pyproject.toml's ``[tool.setuptools.packages.find]`` leaves it out of
the wheel (by its include list, and by name in exclude), so it is importable only from a checkout
(the repository root on ``sys.path``, as pytest and ``python -m bench.<x>`` have it).

Subpackages:
    ros: waits with deadlines, child processes, DDS participant release (any ROS test or bench).
    nav: the in-process node harness on the real map, and a vectorised fake lidar.
    localization: the amcl rig (map_server, amcl, lifecycle manager) and the sim2d tour around it.
    slam: analytic worlds and lidar, the fake robot, the slam node's probe and the exploration stack.
    autonomy: the seed autonomy's fake navigator and its whole-stack runner.
"""
