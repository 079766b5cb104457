"""Stand-ins for ``executor.run_job`` in the Ray backend's tests: runners whose Ray worker dies.

A runner is called inside the Ray task; ``os._exit`` ends the task's worker process the way the OOM
killer or a crash would, so Ray's own retry (``max_retries=1``) is what re-queues the job. Which
attempt this is comes from a flag file in the test cluster's temp dir (its nodes share this machine;
the directory goes with the cluster).
"""

from __future__ import annotations

import os
from pathlib import Path

from navsuite_tools.scenarios.domains import DomainPool
from navsuite_tools.scenarios.executor import Job
from navsuite_tools.scenarios.verdict import Outcome
from tests.helpers.ray_cluster import TAG

DIES_ONCE = "short_goal"  # this scenario's first attempt dies; any other scenario's every attempt does


def die_once_filed() -> None:
    """End this worker process once the ledger has filed this attempt, as a real worker that dies
    into its run would. A fixed lifetime (1 s wall) raced the record: CI run DC lost it, and the re-run
    counted itself as the first attempt."""
    import ray

    from navsuite_tools.scenarios.cluster import RUNNING_ATTEMPT

    attempt = RUNNING_ATTEMPT.get()
    if attempt is not None:
        ray.get(attempt)
    os._exit(1)


def dying_runner(job: Job, domains: DomainPool, marker: str) -> Outcome:
    """Die on the first attempt of DIES_ONCE and on every attempt of the others; otherwise a result
    with one artifact, so the test sees it shipped back."""
    flag = Path(os.environ[TAG]) / f"died-{marker.replace(':', '-')}"
    if job.scenario.name != DIES_ONCE or not flag.exists():
        flag.touch()
        die_once_filed()
    flag.unlink()
    job.artifact_dir.mkdir(parents=True, exist_ok=True)
    log = job.artifact_dir / "worker.log"
    log.write_text("second attempt\n", encoding="utf-8")
    return Outcome("SUCCESS", "fake run", artifacts={"logs": str(log)})
