"""``pytest --scenarios FILE``: every scenario of FILE becomes one test, so mission authors keep pytest.

Registered as a ``pytest11`` entry point (pyproject), so installing navsuite is enough; without the
option the plugin does nothing. With it and no test paths on the command line, only the scenarios are
collected (not the ini's testpaths); with paths, the scenarios come in addition. The tests are named
``FILE::<scenario>``, so ``-k``, ``--lf``, JUnit (``--junitxml``) and pytest-xdist (``-n 2``: each test
still claims its own domain id) work as for any test.

Each test runs its scenario exactly as ``navsuite-scenarios run`` does (navsuite_tools.scenarios.farm on
the local executor, one at a time) and fails with the failing criteria as its message. Artifacts go
to ``--scenarios-out`` (default ``artifacts/scenarios/pytest-<file>``)/<scenario>/.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from navsuite_data import data_dir
from navsuite_tools.scenarios.schema import Scenario


def pytest_addoption(parser: pytest.Parser) -> None:
    group = parser.getgroup("scenarios", "navsuite scenario farm")
    group.addoption("--scenarios", action="append", default=[], metavar="FILE",
                    help="run the scenarios of FILE as tests (repeatable)")
    group.addoption("--scenarios-out", default=None, metavar="DIR",
                    help="artifact directory (default artifacts/scenarios/pytest-<file>)")
    from navsuite_tools.scenarios.domains import DEFAULT_TEXT

    group.addoption("--scenarios-domains", default=os.environ.get("NAVSUITE_SCENARIO_DOMAINS", DEFAULT_TEXT),
                    metavar="FIRST-LAST", help="ROS_DOMAIN_ID range the scenarios claim from (default "
                    f"$NAVSUITE_SCENARIO_DOMAINS or {DEFAULT_TEXT})")


def pytest_configure(config: pytest.Config) -> None:
    files = [str(Path(f).resolve()) for f in config.getoption("scenarios")]
    if not files:
        return
    if config.args_source != pytest.Config.ArgsSource.ARGS:  # no test path named: the scenarios only
        config.args = files
    else:
        config.args = [*config.args, *files]


def pytest_collect_file(file_path: Path, parent: pytest.Collector) -> pytest.Collector | None:
    files = {Path(f).resolve() for f in parent.config.getoption("scenarios")}
    if file_path.resolve() in files:
        return ScenarioFile.from_parent(parent, path=file_path)
    return None


class ScenarioFile(pytest.File):
    """A scenario YAML file; an invalid one is a collection error whose message names the bad field."""

    def collect(self) -> Iterator[pytest.Item]:
        from navsuite_tools.scenarios.executor import STOP_GRACE, hard_limit
        from navsuite_tools.scenarios.schema import ScenarioError, load_scenarios

        try:
            scenarios = load_scenarios(self.path, data_dir("config"))
        except ScenarioError as error:
            raise self.CollectError(str(error)) from error
        for scenario in scenarios:
            item = ScenarioItem.from_parent(self, name=scenario.name, scenario=scenario)
            if self.config.pluginmanager.hasplugin("timeout"):  # pytest-timeout: the farm's deadline + slack
                item.add_marker(pytest.mark.timeout(hard_limit(scenario) + STOP_GRACE + 30.0))
            yield item


class ScenarioFailedError(Exception):
    """A scenario whose run did not meet its criteria (the message lists them)."""


class ScenarioItem(pytest.Item):
    def __init__(self, *, scenario: Scenario, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.scenario = scenario

    def runtest(self) -> None:
        from navsuite_tools.scenarios.domains import DomainPool, parse_range
        from navsuite_tools.scenarios.executor import LocalExecutor
        from navsuite_tools.scenarios.farm import run_all

        out = self.config.getoption("scenarios_out")
        out_dir = Path(out) if out else Path("artifacts") / "scenarios" / f"pytest-{self.path.stem}"
        executor = LocalExecutor(1, DomainPool(*parse_range(self.config.getoption("scenarios_domains"))))
        (result,) = run_all([self.scenario], self.path.resolve(), out_dir.resolve(), executor)
        for key, value in result.outcome.artifacts.items():
            self.user_properties.append((key, value))
        if not result.verdict.passed:
            raise ScenarioFailedError("\n".join([*result.verdict.failures, f"detail: {result.outcome.detail}",
                                            f"artifacts: {result.outcome.artifacts}"]))

    def repr_failure(self, excinfo: pytest.ExceptionInfo[BaseException], style: Any = None) -> Any:
        if isinstance(excinfo.value, ScenarioFailedError):
            return f"scenario {self.name} failed:\n{excinfo.value}"
        return super().repr_failure(excinfo)

    def reportinfo(self) -> tuple[Path, int | None, str]:
        return self.path, None, f"scenario {self.name}"
