"""The package carries its data: a wheel installed outside the repository runs ``navsuite-demo`` (issue 46).

The test builds a wheel of the project, installs it into a fresh virtual environment in the test's
tmp directory, and runs the wheel's own ``navsuite-demo`` console script from a working directory
that is neither the repository nor the environment. It passes only when config/, maps/ and the worlds
travel inside the wheel and are found through ``importlib.resources`` (navsuite_data): a path
derived from the source tree does not exist there.

How the environment stays clean without reinstalling the dependencies (rclpy, numpy, the interface
packages scripts/setup.sh built into .venv): the fresh venv is made ``--without-pip`` and a ``.pth``
line puts the project venv's site-packages on its path. A plain path line in a ``.pth`` file is added
to ``sys.path`` without processing the ``.pth`` files inside it, so the project venv's editable-install
finder (which maps navsuite's packages to the repository) never loads; the repository is not on
``sys.path``, and a check asserts that every navsuite package is imported from the fresh venv. The
interface libraries are found through LD_LIBRARY_PATH, which this session already carries (the
ros_wheels_bootstrapper's re-exec) and hands to the children.

The wheel is built from a copy of the sources, so the build writes nothing into the checkout
(setuptools keeps build/ and *.egg-info next to the sources). One demo run at ``--rtf max``.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import sysconfig
from importlib import metadata
from pathlib import Path

import pytest

from navsuite_testing.ros import REPO

pytestmark = [pytest.mark.slow, pytest.mark.ros]

PACKAGES = ("navsuite_data", "nav_stack", "sim2d", "smacc_py", "ros_tools")
#: Left out of the copy the wheel is built from: version control, environments, caches, outputs.
NOT_SOURCES = (".git", ".venv", "build", "artifacts", "__pycache__", "*.egg-info", ".*_cache", "*.pyc")
#: Shipped files the demo needs, as the installed package must hold them (navsuite_data's layout).
SHIPPED = ("config/nav2_params.yaml", "config/sim2d.yaml", "config/sm_nav2_test_1.yaml",
           "config/trees/navigate_to_pose_w_replanning_and_recovery.xml",
           "maps/turtlebot3_world.yaml", "maps/turtlebot3_world.pgm", "worlds/turtlebot3_world.yaml")
FIRST_SETUPTOOLS_WITH_SPDX_LICENSE = 77  # pyproject's ``license = "Apache-2.0"`` (build-system.requires)


def _build_wheel(src: Path, dist: Path) -> Path:
    """``pip wheel`` of ``src``: with this environment's setuptools when it is recent enough, else in
    pip's isolated build environment (which fetches setuptools as pyproject's build-system says)."""
    isolation: list[str] = []
    try:
        if int(metadata.version("setuptools").split(".")[0]) >= FIRST_SETUPTOOLS_WITH_SPDX_LICENSE:
            isolation = ["--no-build-isolation"]
    except metadata.PackageNotFoundError:
        pass
    built = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--disable-pip-version-check",
                            *isolation, "-w", str(dist), str(src)],
                           capture_output=True, text=True, timeout=300)
    assert built.returncode == 0, built.stdout[-3000:] + built.stderr[-3000:]
    (wheel,) = dist.glob("navsuite-*.whl")
    return wheel


def _fresh_venv(root: Path, wheel: Path) -> tuple[Path, Path]:
    """A venv at ``root`` with the wheel installed and this environment's site-packages (the
    dependencies) on its path; its bin/ and site-packages."""
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(root)], check=True, timeout=120)
    bin_dir = root / "bin"
    purelib = "import sysconfig; print(sysconfig.get_path('purelib'))"
    site = Path(subprocess.run([str(bin_dir / "python"), "-c", purelib], capture_output=True, text=True,
                               check=True, timeout=60).stdout.strip()).resolve()
    (site / "navsuite_test_dependencies.pth").write_text(sysconfig.get_path("purelib") + "\n")
    installed = subprocess.run([sys.executable, "-m", "pip", "--python", str(bin_dir / "python"), "install",
                                "--no-deps", "--no-index", "--disable-pip-version-check", str(wheel)],
                               capture_output=True, text=True, timeout=300)
    assert installed.returncode == 0, installed.stdout[-3000:] + installed.stderr[-3000:]
    return bin_dir, site


def _user_env(bin_dir: Path) -> dict[str, str]:
    """The test's ROS environment (domain id, localhost discovery, LD_LIBRARY_PATH) with the fresh venv's
    bin/ first on PATH (nav-bringup is found there), no PYTHONPATH and no log directory of the session's:
    a user's run writes its logs under its working directory."""
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "NAVSUITE_LOG_DIR", "VIRTUAL_ENV")}
    env["PATH"] = os.pathsep.join([str(bin_dir), env.get("PATH", "")])
    return env


@pytest.mark.timeout(900)
def test_the_installed_wheel_runs_navsuite_demo_outside_the_repository(tmp_path: Path) -> None:
    src = tmp_path / "src"
    shutil.copytree(REPO, src, symlinks=True, ignore=shutil.ignore_patterns(*NOT_SOURCES))
    wheel = _build_wheel(src, tmp_path / "dist")
    bin_dir, site = _fresh_venv(tmp_path / "venv", wheel)
    data = site / "navsuite_data"
    missing = [name for name in SHIPPED if not (data / name).is_file()]
    assert not missing, f"not in the installed wheel: {missing}"
    assert not (data / "config").is_symlink()  # copies, not links back into a checkout
    assert not (site / "sim2d" / "worlds").exists()  # the worlds ship once, as navsuite_data/worlds

    work = tmp_path / "user"  # a user's folder: neither the repository nor the environment
    work.mkdir()
    env = _user_env(bin_dir)
    where = subprocess.run(
        [str(bin_dir / "python"), "-c",
         "import sys, importlib; "
         f"print('\\n'.join(importlib.import_module(p).__file__ for p in {PACKAGES!r})); "
         "print('\\n'.join('path ' + p for p in sys.path))"],
        cwd=work, env=env, capture_output=True, text=True, timeout=120)
    assert where.returncode == 0, where.stderr[-3000:]
    lines = where.stdout.splitlines()
    files = [Path(line) for line in lines if not line.startswith("path ")]
    print("imported from:", *files, sep="\n  ")  # nav_stack.__file__ and the others, for the log
    assert len(files) == len(PACKAGES) and all(file.resolve().is_relative_to(site) for file in files), lines
    paths = [(work / line[len("path "):]).resolve() for line in lines if line.startswith("path ")]  # "": cwd
    assert REPO not in paths, paths

    demo = subprocess.run([str(bin_dir / "navsuite-demo"), "--timeout", "300", "--no-report"],
                          cwd=work, env=env, capture_output=True, text=True, timeout=600)
    output = demo.stdout[-5000:] + demo.stderr[-5000:]
    assert demo.returncode == 0, output
    assert "result: SUCCESS" in demo.stdout, output
    assert f"starting the stack: {bin_dir / 'nav-bringup'}" in demo.stdout, output
    # the stack wrote its logs under the user's folder, and map_server loaded the installed map
    logs = list((work / "artifacts" / "logs").glob("*.log"))
    loaded = [line for log in logs for line in log.read_text(errors="replace").splitlines()
              if "Loaded map " in line]
    assert loaded, [log.name for log in logs]
    assert all(str(data / "maps" / "turtlebot3_world.yaml") in line for line in loaded), loaded
