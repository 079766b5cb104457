"""Find a state machine class from a command-line name: ``sm_nav2_test_1``, a module, or ``module:Class``."""

from __future__ import annotations

import importlib
import inspect

from smacc_py.core import SmaccStateMachineBase

STATE_MACHINES_PACKAGE = "smacc_py.state_machines"


def _import(module_name: str, spec: str) -> object:
    try:
        return importlib.import_module(module_name)
    except ModuleNotFoundError as error:
        if (error.name and module_name.startswith(error.name)) or error.name == module_name:
            raise ValueError(f"state machine {spec!r}: no module {module_name!r}") from None
        raise


def load_state_machine(spec: str) -> type[SmaccStateMachineBase]:
    """Resolve ``spec`` to a machine class; ValueError naming what was tried when it cannot.

    ``sm_nav2_test_1`` means ``smacc_py.state_machines.sm_nav2_test_1``; a module is searched for its
    ``STATE_MACHINE`` attribute, else for the one SmaccStateMachineBase subclass it defines.
    """
    module_name, _, class_name = spec.partition(":")
    if "." not in module_name:
        module_name = f"{STATE_MACHINES_PACKAGE}.{module_name}"
    module = _import(module_name, spec)
    if class_name:
        found = getattr(module, class_name, None)
    else:
        found = getattr(module, "STATE_MACHINE", None)
        if found is None:
            candidates = [
                obj
                for _, obj in inspect.getmembers(module, inspect.isclass)
                if issubclass(obj, SmaccStateMachineBase)
                and obj is not SmaccStateMachineBase
                and obj.__module__.startswith(module_name)
            ]
            if len(candidates) != 1:
                names = ", ".join(c.__name__ for c in candidates) or "none"
                raise ValueError(
                    f"state machine {spec!r}: module {module_name} defines {names}; name one as "
                    f"{module_name}:ClassName or set STATE_MACHINE"
                )
            found = candidates[0]
    if not (isinstance(found, type) and issubclass(found, SmaccStateMachineBase)):
        raise ValueError(f"state machine {spec!r}: {found!r} is not a SmaccStateMachineBase subclass")
    return found
