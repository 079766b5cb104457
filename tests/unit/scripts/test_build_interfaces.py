"""scripts/build_interfaces.py starts packages in dependency order, several at once, and stops on a failure.

No CMake here: the scheduler runs a fake builder that records what ran when.
"""

from __future__ import annotations

import importlib.util
import sys
import threading
from pathlib import Path
from types import ModuleType

import pytest

REPO = Path(__file__).resolve().parents[3]


def load_tool() -> ModuleType:
    path = REPO / "scripts" / "build_interfaces.py"
    spec = importlib.util.spec_from_file_location("build_interfaces", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look the module up while the class is created
    spec.loader.exec_module(module)
    return module


tool = load_tool()


class FakeBuilder:
    """Records start and end of every build.

    The first ``together`` builds wait for each other (a barrier with a deadline), so a scheduler
    that runs fewer of them at once fails the test instead of passing by luck of timing.
    """

    def __init__(self, fail: str | None = None, together: int = 1) -> None:
        self.fail = fail
        self.barrier = threading.Barrier(together, timeout=10.0)
        self.together = together
        self.lock = threading.Lock()
        self.events: list[tuple[str, str]] = []
        self.running = 0
        self.most_running = 0
        self.aborted = False

    def build(self, package: object) -> None:
        name = package.name  # type: ignore[attr-defined]
        with self.lock:
            self.events.append(("start", name))
            self.running += 1
            self.most_running = max(self.most_running, self.running)
            gather = len(self.events) <= self.together
        if gather:
            self.barrier.wait()
        with self.lock:
            self.running -= 1
            self.events.append(("end", name))
        if name == self.fail:
            raise SystemExit(f"{name} failed")

    def abort(self) -> None:
        self.aborted = True


def package(name: str, depends: tuple[str, ...] = (), interfaces: int = 1) -> object:
    return tool.Package(name=name, source=Path(name), depends=frozenset(depends), interfaces=interfaces)


def test_the_repositorys_packages_start_with_what_nav2_msgs_needs() -> None:
    packages = tool.local_packages()
    names = [p.name for p in packages]
    assert set(names) == {"geographic_msgs", "bond", "tf2_msgs", "smacc2_msgs", "nav2_msgs", "slam_toolbox"}
    nav2 = next(p for p in packages if p.name == "nav2_msgs")
    assert nav2.depends == {"geographic_msgs"}
    # geographic_msgs first (nav2_msgs waits for it), then the largest build.
    assert names[:2] == ["geographic_msgs", "nav2_msgs"]


def test_a_package_starts_only_after_its_dependencies_finished() -> None:
    packages = tool.build_order([
        package("leaf", interfaces=50), package("base", interfaces=1), package("app", ("leaf", "base")),
    ])
    builder = FakeBuilder(together=2)  # leaf and base build side by side
    tool.build_all(packages, builder, slots=2)
    events = builder.events
    app_start = events.index(("start", "app"))
    assert events.index(("end", "leaf")) < app_start
    assert events.index(("end", "base")) < app_start


def test_never_more_builds_at_once_than_slots() -> None:
    packages = tool.build_order([package(f"p{i}") for i in range(6)])
    builder = FakeBuilder(together=3)
    tool.build_all(packages, builder, slots=3)
    assert builder.most_running == 3
    assert sorted(name for kind, name in builder.events if kind == "end") == [f"p{i}" for i in range(6)]


def test_a_failure_stops_the_build_and_starts_nothing_after_it() -> None:
    packages = tool.build_order([package("base", interfaces=9), package("app", ("base",))])
    builder = FakeBuilder(fail="base")
    with pytest.raises(SystemExit, match="base failed"):
        tool.build_all(packages, builder, slots=2)
    assert builder.aborted
    assert ("start", "app") not in builder.events


def test_a_dependency_on_an_unknown_package_is_reported() -> None:
    with pytest.raises(SystemExit, match="unknown"):
        tool.build_order([package("app", ("missing",))])


def test_a_dependency_cycle_is_reported() -> None:
    with pytest.raises(SystemExit, match="cycle"):
        tool.build_order([package("a", ("b",)), package("b", ("a",))])
