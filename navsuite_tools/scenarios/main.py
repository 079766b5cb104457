"""``navsuite-scenarios``: run a scenario file, each scenario isolated, and say which ones passed.

Examples::

    navsuite-scenarios run config/scenarios/seed_missions.yaml --workers 2
    navsuite-scenarios run config/scenarios/seed_missions.yaml -k seed_nominal -k 'patrol_*'
    navsuite-scenarios check config/scenarios/seed_missions.yaml     # validate and list, run nothing
    navsuite-scenarios run config/scenarios/seed_missions.yaml --ray auto   # on a Ray cluster
    navsuite-scenarios rerun artifacts/scenarios/seed_missions-20261129-101500 kidnap_first_waypoint

Each scenario runs as its own processes (the mission command, its stack, a recorder) on a ROS domain
id claimed for it alone (``--domains``, default 51-100), localhost discovery, lockstep at ``--rtf max``.
Its recording, run report and logs go to ``<out>/<scenario>/``; ``<out>/summary.html`` and
``<out>/junit.xml`` sum the run up. With ``--ray ADDRESS`` the scenarios run as Ray tasks on a cluster
(``cluster``; ``pip install navsuite[cluster]``) and their artifacts come back here. Exit status: 0
when every selected scenario passed, 1 when one failed, 2 on an invalid file or arguments (or Ray
missing or unreachable), 130 on Ctrl-C (every process of the run is stopped).

``rerun RUN_DIR NAME`` replays one scenario of an earlier run from the very scenario file it used and
says whether the replay is the recording (navsuite_tools/scenarios/rerun.py): exit 0 when identical, 1
when the two part (named: the first sim time and topic), 2 when it cannot replay exactly.
"""

from __future__ import annotations

import argparse
import os
import signal
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from navsuite_data import data_dir, resolve, searched
from navsuite_tools.scenarios import domains
from navsuite_tools.scenarios.schema import Scenario, ScenarioError, load_scenarios

if TYPE_CHECKING:
    from navsuite_tools.scenarios.executor import Executor

EXIT_OK, EXIT_FAILED, EXIT_USAGE, EXIT_INTERRUPTED = 0, 1, 2, 130


def parse_args(argv: Sequence[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(prog="navsuite-scenarios", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    for name in ("run", "check"):
        cmd = sub.add_parser(name, help="run the scenarios" if name == "run" else "validate and list them")
        cmd.add_argument("file", type=Path, help="scenario YAML file")
        cmd.add_argument("-k", dest="select", action="append", default=[], metavar="NAME",
                         help="only scenarios whose name contains NAME or matches it as a glob (repeatable)")
    run = sub.choices["run"]
    run.add_argument("--workers", type=int, default=1, help="scenarios at a time (default 1)")
    run.add_argument("--out", type=Path, default=None,
                     help="output directory (default artifacts/scenarios/<file>-<UTC time>)")
    run.add_argument("--ray", metavar="ADDRESS", default=None,
                     help="run on the Ray cluster at ADDRESS (host:port, or 'auto' for the one started on "
                          "this machine) instead of local workers; needs pip install navsuite[cluster]")
    run.add_argument("--ray-cpus", type=float, default=1.0, metavar="N",
                     help="CPUs each scenario's Ray task asks for (default 1)")
    rerun = sub.add_parser("rerun", help="replay one scenario of an earlier run and compare the recordings")
    rerun.add_argument("run_dir", type=Path, help="the earlier run's output directory (it holds farm.json)")
    rerun.add_argument("name", help="the scenario to replay")
    rerun.add_argument("--out", type=Path, default=None,
                       help="output directory (default RUN_DIR/rerun-<NAME>-<UTC time>)")
    for command in (run, rerun):
        command.add_argument(
            "--domains", default=os.environ.get("NAVSUITE_SCENARIO_DOMAINS", domains.DEFAULT_TEXT),
            help="ROS_DOMAIN_ID range the runs claim from, FIRST-LAST (default "
                 f"$NAVSUITE_SCENARIO_DOMAINS or {domains.DEFAULT_TEXT}; ids held by test sessions, "
                 "benchmarks or other farms are skipped)")
    options = parser.parse_args(argv)
    if options.command == "run":
        if options.workers < 1:
            parser.error(f"--workers must be >= 1, got {options.workers}")
        if options.ray_cpus <= 0:
            parser.error(f"--ray-cpus must be > 0, got {options.ray_cpus}")
    if options.command in ("run", "rerun"):
        try:
            options.domains = domains.parse_range(options.domains)
        except ValueError as error:
            parser.error(f"--domains: {error}")
    return options


def main(argv: Sequence[str] | None = None) -> int:
    from navsuite_tools.scenarios.farm import select

    options = parse_args(argv)
    if options.command == "rerun":
        return replay(options)
    source = resolve(options.file)  # the user's file, else a shipped one (config/scenarios/...)
    if not source.is_file():
        print(f"navsuite-scenarios: {options.file}: no such file ({searched(options.file)})", file=sys.stderr)
        return EXIT_USAGE
    options.file = source
    try:
        scenarios = select(load_scenarios(options.file, data_dir("config")), options.select)
    except ScenarioError as error:
        print(f"navsuite-scenarios: {error}", file=sys.stderr)
        return EXIT_USAGE
    if not scenarios:
        print(f"navsuite-scenarios: no scenario of {options.file} matches {options.select}", file=sys.stderr)
        return EXIT_USAGE
    if options.command == "check":
        for scenario in scenarios:
            print(f"{scenario.name}: {type(scenario.mission).__name__} in {scenario.world}, "
                  f"{len(scenario.events)} event(s)")
        print(f"{len(scenarios)} scenario(s) valid")
        return EXIT_OK
    # Ctrl-C stops the run even when the shell started this process with SIGINT ignored (a
    # background job of a non-interactive shell, as CI scripts start their tests): Python then keeps
    # the inherited SIG_IGN, and the interrupt would go unheard while every scenario ran to the end.
    signal.signal(signal.SIGINT, signal.default_int_handler)
    return run(options, scenarios)


def replay(options: argparse.Namespace) -> int:
    """``rerun``: one scenario of an earlier run, on one local worker (rerun.py says how it is judged)."""
    from navsuite_tools.scenarios.executor import LocalExecutor
    from navsuite_tools.scenarios.rerun import rerun

    stamp = time.strftime("%Y%m%d-%H%M%S", time.gmtime())
    out_dir = (options.out or options.run_dir / f"rerun-{options.name}-{stamp}").resolve()
    signal.signal(signal.SIGINT, signal.default_int_handler)  # as for run (main says why)
    executor = LocalExecutor(1, domains.DomainPool(*options.domains))
    try:
        return rerun(options.run_dir.resolve(), options.name, out_dir, executor, data_dir("config"))
    except KeyboardInterrupt:
        executor.shutdown(cancel=True)
        print("navsuite-scenarios: interrupted; every scenario process was stopped", flush=True)
        return EXIT_INTERRUPTED


def executor_for(options: argparse.Namespace) -> tuple[Executor, str]:
    """The backend ``options`` ask for and how to name it; RuntimeError or ConnectionError when Ray is
    asked for and is not installed or not reachable."""
    if options.ray is None:
        from navsuite_tools.scenarios.executor import LocalExecutor

        pool = domains.DomainPool(*options.domains)
        return LocalExecutor(options.workers, pool), f"{options.workers} at a time"
    from navsuite_tools.scenarios.cluster import RayExecutor

    return (RayExecutor(options.ray, options.domains, options.ray_cpus),
            f"Ray tasks of {options.ray_cpus:g} CPU on the cluster at {options.ray}")


def run(options: argparse.Namespace, scenarios: list[Scenario]) -> int:
    from navsuite_tools.scenarios.farm import run_all
    from navsuite_tools.scenarios.summary import write_summary
    from navsuite_tools.scenarios.table import LiveTable

    stamp = time.strftime("%Y%m%d-%H%M%S", time.gmtime())
    out_dir = (options.out or Path("artifacts") / "scenarios" / f"{options.file.stem}-{stamp}").resolve()
    try:
        executor, how = executor_for(options)
    except (RuntimeError, ConnectionError) as error:
        print(f"navsuite-scenarios: {error}", file=sys.stderr)
        return EXIT_USAGE
    table = LiveTable([s.name for s in scenarios], sys.stdout)
    print(f"navsuite-scenarios: {len(scenarios)} scenario(s) from {options.file}, {how}, "
          f"domains {options.domains[0]}-{options.domains[1]}; artifacts in {out_dir}/", flush=True)
    started = time.monotonic()
    try:
        results = run_all(scenarios, options.file.resolve(), out_dir, executor, table.start,
                          lambda r: table.finish(r.scenario.name, r.outcome, r.verdict), table.tick)
    except KeyboardInterrupt:
        print("navsuite-scenarios: interrupted; every scenario process was stopped", flush=True)
        return EXIT_INTERRUPTED
    wall = time.monotonic() - started
    page, junit = write_summary(out_dir, options.file.stem, results, wall)
    failed = [r for r in results if not r.verdict.passed]
    print(f"{len(results) - len(failed)} passed, {len(failed)} failed in {wall:.0f} s wall "
          f"({len(results) / wall * 3600:.0f} scenarios/h); summary {page}, JUnit {junit}", flush=True)
    for result in results:
        if result.outcome.attempts > 1:
            print(f"RE-QUEUED {result.scenario.name}: its worker died; attempt {result.outcome.attempts} "
                  f"{'passed' if result.verdict.passed else 'failed'}", flush=True)
    for result in failed:
        print(f"FAILED {result.scenario.name}: {result.verdict.describe()}", flush=True)
    return EXIT_FAILED if failed else EXIT_OK


if __name__ == "__main__":
    sys.exit(main())
