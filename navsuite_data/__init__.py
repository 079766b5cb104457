"""navsuite's shipped data, found the same way in a source checkout and in an installed wheel.

Layout of the package (``importlib.resources.files("navsuite_data")``)::

    config/   Nav2-style parameter files, trees/, scenarios/, docks/, locations.yaml  (repo: config/)
    maps/     map_server maps, each YAML next to its image                           (repo: maps/)
    worlds/   sim2d's world files                                                     (repo: sim2d/worlds/)

Why a package of its own: sim2d, nav_stack and smacc_py never import each other and the cores may
not import ros_tools, yet they all read this data (docs/architecture.md, rule 2: they meet on the ROS
graph and in the data of maps/ and config/). So the data belongs to none of them, and every lookup goes
through the functions below instead of ``Path(__file__).parents[N]`` guesses that held only in a
checkout. In the checkout the three folders are symbolic links to the repository's own, so the tree
keeps its folders and docs and tests their paths; building a wheel follows the links and ships copies
(pyproject.toml, ``[tool.setuptools.packages.find]``).

Paths handed to another process or to a map loader must be real files: ``as_file`` makes them (a
no-op for an unpacked install, which is what pip makes; an install inside a zip archive needs Python
3.12 or newer, whose ``as_file`` extracts whole folders, so a map keeps its image beside it).

User paths come first everywhere: :func:`resolve` returns a path as given when it exists (absolute,
or relative to the working directory), and only then the shipped file of the same name. Stdlib only,
so the pure cores may use it.
"""

from __future__ import annotations

import atexit
from contextlib import ExitStack
from functools import cache
from importlib import resources
from pathlib import Path, PurePosixPath

#: The data folders of the package, and the repository folder each one mirrors (how users, docs and
#: parameter files spell a relative path to it).
SOURCE_FOLDERS = {"config": "config", "maps": "maps", "worlds": "sim2d/worlds"}
KINDS = tuple(SOURCE_FOLDERS)

_extracted = ExitStack()  # folders as_file had to extract (zip installs), removed at exit
atexit.register(_extracted.close)


@cache
def data_dir(kind: str) -> Path:
    """The real folder of one kind of data (one of KINDS): the repository's folder in a checkout,
    the installed package's otherwise."""
    if kind not in SOURCE_FOLDERS:
        raise ValueError(f"navsuite_data: no data folder {kind!r} (known: {', '.join(KINDS)})")
    folder = _extracted.enter_context(resources.as_file(resources.files(__name__) / kind))
    return Path(folder).resolve()


def data_root() -> Path:
    """The folder that holds config/ and maps/: the repository in a checkout, the package when
    installed. Relative paths such as ``config/locations.yaml`` mean the same below both."""
    return data_dir("config").parent


def config_path(name: str | Path) -> Path:
    """A shipped configuration file, e.g. ``config_path("nav2_params.yaml")`` or ``"trees/x.xml"``."""
    return data_dir("config") / name


def map_path(name: str | Path) -> Path:
    """A shipped map_server YAML, e.g. ``map_path("turtlebot3_world.yaml")`` (its image sits beside it)."""
    return data_dir("maps") / name


def world_path(name: str | Path) -> Path:
    """A shipped sim2d world file, e.g. ``world_path("office_small.yaml")``."""
    return data_dir("worlds") / name


def shipped(path: str | Path) -> Path | None:
    """The shipped file a relative path names as it would in the repository (``config/x.yaml``,
    ``maps/x.yaml``, ``sim2d/worlds/x.yaml``), existing or not; None for any other path."""
    relative = PurePosixPath(Path(path).as_posix())
    if relative.is_absolute():
        return None
    for kind, folder in SOURCE_FOLDERS.items():
        prefix = PurePosixPath(folder).parts
        if relative.parts[:len(prefix)] == prefix:
            return data_dir(kind).joinpath(*relative.parts[len(prefix):])
    return None


def resolve(path: str | Path) -> Path:
    """A user's path: as given when it exists or is absolute (relative paths start from the working
    directory), else the shipped file of that name when there is one, else as given (the caller's
    error names it, with :func:`searched` for where it was looked for)."""
    given = Path(path).expanduser()
    if given.is_absolute() or given.exists():
        return given
    candidate = shipped(given)
    return candidate if candidate is not None and candidate.exists() else given


def searched(path: str | Path) -> str:
    """Where :func:`resolve` looks for ``path``, for an error message: ``looked at A and B``."""
    given = Path(path).expanduser()
    places = [given if given.is_absolute() else Path.cwd() / given]
    candidate = shipped(given)
    if candidate is not None:
        places.append(candidate)
    return "looked at " + " and ".join(str(place) for place in places)
