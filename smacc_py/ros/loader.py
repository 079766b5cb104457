"""Find a state machine class from a command-line name; the one loader of ``smacc-run`` and ``smacc-graph``.

A spec is ``TARGET`` or ``TARGET:ClassName``. TARGET is tried, in this order, as

1. a shipped machine: ``sm_nav2_test_1`` is ``smacc_py.state_machines.sm_nav2_test_1``;
2. a module path, importable from ``sys.path`` or the current directory (as ``python -m`` would):
   ``my_pkg.sm_foo``;
3. a file path: a module file (``./sm_foo.py``) or a package folder (``./sm_my_machine``, what
   ``smacc-new`` writes). The folder holding the outermost package (or the file, when it is not in a
   package) goes first on ``sys.path`` and the module is imported under its dotted name, so the
   machine's own absolute and relative imports work as they do in its tests.

A path-like TARGET (with a ``/`` or ending in ``.py``) is only tried as a path. In the module found,
the machine is ``ClassName``, else the ``STATE_MACHINE`` attribute, else the one SmaccStateMachineBase
subclass the module (or package) defines; a package with none is looked into for the module of its own
name (``sm_my_machine/sm_my_machine.py``, SMACC2's layout). A TARGET found nowhere raises
``MachineNotFoundError`` (a ValueError) whose message lists every place looked; an error raised by the
machine's own code while importing it (a missing dependency, a syntax error) propagates unchanged.
"""

from __future__ import annotations

import importlib
import inspect
import os
import pkgutil
import sys
from pathlib import Path
from types import ModuleType

from smacc_py.core import SmaccStateMachineBase

STATE_MACHINES_PACKAGE = "smacc_py.state_machines"


class MachineNotFoundError(ValueError):
    """No state machine under that name; the message says everywhere it was looked for."""


def shipped_machines() -> list[str]:
    """Names of the machines in ``smacc_py.state_machines``."""
    package = importlib.import_module(STATE_MACHINES_PACKAGE)
    return sorted(info.name for info in pkgutil.iter_modules(package.__path__) if info.ispkg)


def _import_if_present(module_name: str) -> ModuleType | None:
    """The module, or None when ``module_name`` itself (or a package above it) does not exist."""
    try:
        return importlib.import_module(module_name)
    except ModuleNotFoundError as error:
        missing = error.name or ""
        if module_name == missing or module_name.startswith(missing + "."):
            return None
        raise  # the machine imports something that is missing: its own error, with its traceback


def _is_path(target: str) -> bool:
    return "/" in target or os.sep in target or target.endswith(".py") or target in (".", "..")


def _module_name_of(path: Path) -> tuple[Path, str] | str:
    """(folder to put on sys.path, dotted module name) for a file or package folder, or why it is none."""
    if path.is_dir():
        if not (path / "__init__.py").is_file():
            return f"folder {path} is not a Python package (no __init__.py)"
        names, folder = [], path
    elif path.is_file() and path.suffix == ".py":
        names = [] if path.stem == "__init__" else [path.stem]
        folder = path.parent
    else:
        return f"no module file or package folder {path}"
    while (folder / "__init__.py").is_file():
        names.insert(0, folder.name)
        folder = folder.parent
    bad = [name for name in names if not name.isidentifier()]
    if bad:
        return f"{path}: {bad[0]!r} is not a valid Python module name"
    return folder, ".".join(names)


def _import_path(path: Path) -> ModuleType | str:
    """Import a module file or package folder under its dotted name, or say why it cannot be."""
    found = _module_name_of(path.resolve())
    if isinstance(found, str):
        return found
    root, module_name = found
    top = module_name.partition(".")[0]
    loaded = sys.modules.get(top)
    if loaded is not None:
        origin = Path(getattr(loaded, "__file__", None) or next(iter(getattr(loaded, "__path__", [])), "."))
        if root not in origin.resolve().parents:
            return (f"{path}: another module named {top!r} is already imported (from {origin}); rename the "
                    "machine's package")
    if str(root) not in sys.path:
        sys.path.insert(0, str(root))
    module = _import_if_present(module_name)
    return module if module is not None else f"{path}: importing {module_name} from {root} found nothing"


def _find_module(target: str, looked: list[str]) -> ModuleType | None:
    """Try ``target`` as a shipped name, a module path, then a file path; note each failure in ``looked``."""
    if not _is_path(target):
        if all(part.isidentifier() for part in target.split(".")):
            shipped = f"{STATE_MACHINES_PACKAGE}.{target}"
            module = _import_if_present(shipped)
            if module is not None:
                return module
            looked.append(f"shipped machines: no {shipped} (shipped: {', '.join(shipped_machines())})")
            cwd = os.getcwd()
            if cwd not in sys.path and "" not in sys.path:
                sys.path.append(cwd)
            module = _import_if_present(target)
            if module is not None:
                return module
            looked.append(f"module path: no module {target!r} on sys.path or in the current directory {cwd}")
        else:
            looked.append(f"module path: {target!r} is not a dotted module name")
    candidates = [Path(target)] if _is_path(target) else [Path(target), Path(target + ".py")]
    for path in candidates:
        if path.exists():
            found = _import_path(path)
            if isinstance(found, ModuleType):
                return found
            looked.append(f"file path: {found}")
            return None
    names = " or ".join(str(p.resolve()) for p in candidates)
    looked.append(f"file path: no file or folder {names}")
    return None


def _machines_in(module: ModuleType) -> list[type[SmaccStateMachineBase]]:
    name = module.__name__
    return [obj for _, obj in inspect.getmembers(module, inspect.isclass)
            if issubclass(obj, SmaccStateMachineBase) and obj is not SmaccStateMachineBase
            and (obj.__module__ == name or obj.__module__.startswith(name + "."))]


def _machine_of(module: ModuleType, spec: str, class_name: str) -> type[SmaccStateMachineBase]:
    if class_name:
        found = getattr(module, class_name, None)
        if found is None:
            raise MachineNotFoundError(f"state machine {spec!r}: module {module.__name__} has no "
                                       f"{class_name}")
    else:
        found = getattr(module, "STATE_MACHINE", None)
        if found is None:
            candidates = _machines_in(module)
            leaf = module.__name__.rpartition(".")[2]
            if not candidates and hasattr(module, "__path__"):  # SMACC2's layout: sm_x/sm_x.py
                inner = _import_if_present(f"{module.__name__}.{leaf}")
                candidates = _machines_in(inner) if inner is not None else []
            if len(candidates) != 1:
                names = ", ".join(c.__name__ for c in candidates) or "none"
                raise MachineNotFoundError(
                    f"state machine {spec!r}: module {module.__name__} defines {names}; name one as "
                    f"{spec.rpartition(':')[0] or spec}:ClassName or set STATE_MACHINE in the module"
                )
            found = candidates[0]
    if not (isinstance(found, type) and issubclass(found, SmaccStateMachineBase)):
        raise MachineNotFoundError(f"state machine {spec!r}: {found!r} is not a SmaccStateMachineBase "
                                   "subclass")
    return found


def load_state_machine(spec: str) -> type[SmaccStateMachineBase]:
    """Resolve ``spec`` to a machine class (see the module doc); MachineNotFoundError saying where it
    looked when nothing matches."""
    target, colon, class_name = spec.rpartition(":")
    if not colon or not class_name.isidentifier() or not target:
        target, class_name = spec, ""
    looked: list[str] = []
    module = _find_module(target, looked)
    if module is None:
        lines = "\n".join(f"  - {line}" for line in looked)
        raise MachineNotFoundError(f"state machine {spec!r} not found; looked in:\n{lines}")
    return _machine_of(module, spec, class_name)
