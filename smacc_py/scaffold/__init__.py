"""``smacc-new sm_my_machine [--dir PATH]``: write a runnable state-machine package to start from.

The package (``PATH/sm_my_machine``) has SMACC2's reference-machine layout: the machine module, one
state in ``states/``, one orthogonal in ``orthogonals/`` holding one client of ``clients/`` with one
client behavior, and a pytest test that runs the machine on ``smacc_py.testing``'s stand-ins. It runs
as written (``smacc-run ./sm_my_machine``), its test passes, and it passes ruff. An existing folder is
never overwritten, and a name that would shadow an importable module (``json``, ``smacc_py``) is
refused, since the package's folder goes first on ``sys.path`` when it runs.
"""

from __future__ import annotations

import argparse
import importlib.util
import keyword
import re
import sys
from collections.abc import Sequence
from pathlib import Path
from string import Template

from smacc_py.scaffold.templates import FILES

NAME = re.compile(r"[a-z][a-z0-9_]*\Z")


class ScaffoldError(ValueError):
    """The package cannot be written; the message says why."""


def class_name(package: str) -> str:
    """``sm_my_machine`` → ``SmMyMachine``."""
    return "".join(part[:1].upper() + part[1:] for part in package.split("_") if part)


def check_name(package: str) -> None:
    """ScaffoldError unless ``package`` is a new lower-case module name."""
    if not NAME.match(package) or keyword.iskeyword(package):
        raise ScaffoldError(f"{package!r} is not a lower-case Python module name (like sm_my_machine)")
    if importlib.util.find_spec(package) is not None:
        raise ScaffoldError(f"a module named {package!r} can already be imported here; choose another name "
                            "(SMACC2's machines start with sm_)")


def write_package(package: str, parent: Path) -> list[Path]:
    """Write the package ``parent/package``; returns the files written. ScaffoldError when the name is
    bad or the folder exists."""
    root = parent / package
    if root.exists():
        raise ScaffoldError(f"{root} already exists; not overwriting it")
    check_name(package)
    names = {"pkg": package, "Sm": class_name(package)}
    written = []
    for relative, text in FILES.items():
        path = root / Template(relative).substitute(names)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(Template(text).substitute(names))
        written.append(path)
    return written


def _shown(path: Path) -> str:
    """``path`` relative to the current directory when inside it (``./sm_x``), else absolute."""
    try:
        return f"./{path.resolve().relative_to(Path.cwd().resolve())}"
    except ValueError:
        return str(path.resolve())


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="smacc-new", description=__doc__.splitlines()[0])
    parser.add_argument("name", help="the package and machine name, e.g. sm_my_machine (class SmMyMachine)")
    parser.add_argument("--dir", type=Path, default=Path("."), help="where to create it (default: here)")
    options = parser.parse_args(argv)
    try:
        written = write_package(options.name, options.dir)
    except (ScaffoldError, OSError) as error:
        print(f"smacc-new: {error}", file=sys.stderr)
        return 2
    root = _shown(options.dir / options.name)
    print(f"smacc-new: wrote {root} ({len(written)} files, machine {class_name(options.name)})")
    print(f"  run it:   smacc-run {root}")
    print(f"  graph:    smacc-graph {root}")
    print(f"  test it:  python -m pytest {root}/tests")
    return 0


if __name__ == "__main__":
    sys.exit(main())
