"""smacc_py.ros.loader: shipped names, module paths, module files and package folders, and the message
that lists every place looked when a name resolves nowhere (smacc-run and smacc-graph exit 2 on it).

Each test writes its machines under its own tmp_path with module names of its own, and the fixture
puts sys.path, sys.modules and the working directory back afterwards.
"""

from __future__ import annotations

import sys
import textwrap
from collections.abc import Iterator
from pathlib import Path

import pytest

from smacc_py.ros import graph_cli, runner
from smacc_py.ros.loader import MachineNotFoundError, load_state_machine
from smacc_py.scaffold import write_package
from smacc_py.state_machines.sm_nav2_test_1 import SmNav2Test1

MACHINE = textwrap.dedent('''
    from smacc_py.core import SmaccState, SmaccStateMachineBase


    class StOnly(SmaccState, parent="{sm}"):
        pass


    class {sm}(SmaccStateMachineBase):
        initial_state = StOnly
''')


@pytest.fixture(autouse=True)
def _restore_import_state(monkeypatch: pytest.MonkeyPatch) -> Iterator[None]:
    path, modules = list(sys.path), set(sys.modules)
    yield
    sys.path[:] = path
    for name in set(sys.modules) - modules:
        del sys.modules[name]


def _module_file(folder: Path, module: str, sm: str) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"{module}.py"
    path.write_text(MACHINE.format(sm=sm))
    return path


def test_a_shipped_name_is_a_machine_of_smacc_py_state_machines() -> None:
    assert load_state_machine("sm_nav2_test_1") is SmNav2Test1
    assert load_state_machine("smacc_py.state_machines.sm_nav2_test_1:SmNav2Test1") is SmNav2Test1


def test_a_module_path_is_found_on_sys_path_or_in_the_working_directory(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    package = tmp_path / "loader_pkg_a"
    package.mkdir()
    (package / "__init__.py").write_text("")
    _module_file(package, "sm_dotted", "SmDotted")
    monkeypatch.chdir(tmp_path)
    assert load_state_machine("loader_pkg_a.sm_dotted").__name__ == "SmDotted"


def test_a_module_file_and_a_package_folder_load_by_path_with_their_imports(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    flat = _module_file(tmp_path / "flat", "sm_loader_flat", "SmLoaderFlat")
    assert load_state_machine(str(flat)).__name__ == "SmLoaderFlat"
    # smacc-new's package: relative imports across states/, orthogonals/, clients/; STATE_MACHINE
    write_package("sm_loader_scaffold", tmp_path)
    monkeypatch.chdir(tmp_path)
    machine = load_state_machine("./sm_loader_scaffold")
    assert machine.__name__ == "SmLoaderScaffold"
    assert machine.__module__ == "sm_loader_scaffold.sm_loader_scaffold"
    assert load_state_machine("./sm_loader_scaffold/sm_loader_scaffold.py:SmLoaderScaffold") is machine
    assert machine.validate().initial.__name__ == "StState1"


def test_a_package_without_a_machine_is_looked_into_for_its_namesake_module(tmp_path: Path) -> None:
    package = tmp_path / "sm_loader_layout"
    package.mkdir()
    (package / "__init__.py").write_text('"""Exports nothing."""\n')
    _module_file(package, "sm_loader_layout", "SmLoaderLayout")
    assert load_state_machine(str(package)).__name__ == "SmLoaderLayout"


def test_a_name_found_nowhere_lists_every_place_looked(tmp_path: Path,
                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    with pytest.raises(MachineNotFoundError) as caught:
        load_state_machine("sm_nowhere_to_be_found")
    message = str(caught.value)
    assert "shipped machines: no smacc_py.state_machines.sm_nowhere_to_be_found" in message
    assert "sm_nav2_test_1" in message  # the shipped names are listed
    assert ("module path: no module 'sm_nowhere_to_be_found' on sys.path or in the current directory "
            f"{tmp_path}") in message
    assert f"file path: no file or folder {tmp_path}/sm_nowhere_to_be_found or " \
           f"{tmp_path}/sm_nowhere_to_be_found.py" in message
    with pytest.raises(MachineNotFoundError, match=r"file path: folder .*plain is not a Python package"):
        (tmp_path / "plain").mkdir()
        load_state_machine("./plain")


def test_smacc_run_and_smacc_graph_exit_2_naming_the_places(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.chdir(tmp_path)
    assert runner.main(["sm_nowhere_to_be_found"]) == 2
    assert graph_cli.main(["sm_nowhere_to_be_found"]) == 2
    err = capsys.readouterr().err
    assert err.count("smacc-run: state machine 'sm_nowhere_to_be_found' not found") == 1
    assert err.count("smacc-graph: state machine 'sm_nowhere_to_be_found' not found") == 1
    assert err.count("  - shipped machines:") == 2 and err.count("  - file path:") == 2


def test_the_machines_own_import_errors_are_not_reported_as_not_found(tmp_path: Path) -> None:
    broken = tmp_path / "sm_loader_broken.py"
    broken.write_text("import a_dependency_nobody_installed\n")
    with pytest.raises(ModuleNotFoundError, match="a_dependency_nobody_installed"):
        load_state_machine(str(broken))


def test_a_module_of_that_name_imported_from_elsewhere_is_refused(tmp_path: Path) -> None:
    first = _module_file(tmp_path / "one", "sm_loader_twice", "SmLoaderTwice")
    second = _module_file(tmp_path / "two", "sm_loader_twice", "SmLoaderTwice")
    load_state_machine(str(first))
    with pytest.raises(MachineNotFoundError, match=r"another module named 'sm_loader_twice' is already"):
        load_state_machine(str(second))


def test_several_machines_in_one_module_need_a_class_name(tmp_path: Path) -> None:
    path = tmp_path / "sm_loader_pair.py"
    second = MACHINE.format(sm="SmLoaderB").replace("StOnly", "StOther")
    path.write_text(MACHINE.format(sm="SmLoaderA") + second)
    with pytest.raises(MachineNotFoundError, match=r"defines SmLoaderA, SmLoaderB; name one as .*:ClassName"):
        load_state_machine(str(path))
    assert load_state_machine(f"{path}:SmLoaderB").__name__ == "SmLoaderB"
