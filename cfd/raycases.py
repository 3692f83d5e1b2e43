"""Case-level parallelism on a Ray cluster: ``vessel-cfd run ... --ray ADDRESS`` (or ``--ray local``).

The mesh and the base tow run on this machine as always (every other case starts from them); the
independent cases that follow (tows at other speeds, drift angles, sway and yaw runs) are Ray tasks, one
case each, each solving its OpenFOAM case in its own folder with :meth:`Pipeline.execute`, which writes the
same files and the same done marker as a local run. So the cases folder must be on storage every Ray node
sees at the same path (a shared file system), and every node needs OpenFOAM and this package.

Resume is decided here, before anything is sent: a case whose done marker matches is skipped exactly as
in a local run. A task asks for as many Ray CPUs as the case's MPI processes (1, or ``procs`` on a mesh
of :data:`cfd.pipeline.PARALLEL_CELLS` cells or more). Ctrl-C or SIGTERM cancels the tasks: a running
task gets a KeyboardInterrupt, on which :func:`cfd.runner.run_app` terminates its solver's process group;
finished cases keep their markers and a rerun skips them.
"""

from __future__ import annotations

import signal
import threading
import time
from typing import TYPE_CHECKING, Any

from .errors import InputError
from .runner import TERMINATE_GRACE_S, stop_all

if TYPE_CHECKING:
    from .jobs import Job

# the pipeline is passed in, not imported: cfd.pipeline imports this module (for --ray only)
Pipeline = Any


def _ray():
    try:
        import ray  # noqa: PLC0415 - an optional extra, only for --ray
    except ImportError:
        raise InputError("ray", "--ray needs Ray: pip install 'vessel-gym[ray]'") from None
    return ray


def connect(address: str, procs: int) -> int:
    """Join the Ray cluster at ``address`` ("local": start one on this machine with ``procs`` CPUs), unless
    this process is already connected; return the cluster's CPU count."""
    ray = _ray()
    if not ray.is_initialized():
        main = threading.current_thread() is threading.main_thread()
        # ray.init makes SIGTERM exit the process; the CLI's own handlers (SIGTERM as Ctrl-C, which stops
        # the solvers and keeps finished cases) are put back
        handlers = {sig: signal.getsignal(sig) for sig in (signal.SIGINT, signal.SIGTERM)} if main else {}
        try:
            if address == "local":
                ray.init(num_cpus=procs, include_dashboard=False, log_to_driver=True)
            else:
                ray.init(address=address, include_dashboard=False, log_to_driver=True)
        except (ConnectionError, ValueError, RuntimeError) as exc:
            raise InputError("ray", f"cannot connect to the Ray cluster at {address!r}: {exc}") from None
        finally:
            for sig, handler in handlers.items():
                if handler is not None:
                    signal.signal(sig, handler)
    return max(1, int(ray.cluster_resources().get("CPU", 1)))


def _execute(pipeline: Pipeline, job: Job, procs: int) -> tuple[dict[str, Any], float]:
    return pipeline.execute(job, procs)


def run_on_ray(pipeline: Pipeline, jobs: list[Job]) -> None:
    """Run ``jobs`` (independent cases) as Ray tasks and set each one's ``summary``; the pipeline's
    progress, case numbers, wall times and ETA are kept here, in the driver, as for local threads."""
    ray = _ray()
    per = pipeline.per_case_procs
    task = ray.remote(_execute).options(num_cpus=per, max_retries=0)
    shared = ray.put(pipeline)  # sent once: the hull and the job list are the same for every case
    running: dict[Any, tuple[Job, str]] = {}
    for job in jobs:
        done = pipeline.skip(job)
        if done is not None:
            job.summary = done
            continue
        number = pipeline.case_number()
        pipeline.progress(job.label, f"{number} sent to Ray ({pipeline.cases / job.name})")
        running[task.remote(shared, job, per)] = (job, number)
    pending = list(running)
    try:
        while pending:
            ready, pending = ray.wait(pending, num_returns=1, timeout=1.0)
            for ref in ready:
                job, number = running[ref]
                try:
                    summary, wall = ray.get(ref)
                except ray.exceptions.RayTaskError as exc:  # the case's own error, as a local run gives it
                    raise exc.cause from None
                job.summary = summary
                pipeline.finished(job, number, wall)
    except BaseException:  # a failed case, Ctrl-C or SIGTERM: stop the others, keep the finished ones
        stop_all()
        for ref in pending:
            ray.cancel(ref)  # KeyboardInterrupt in a running task: run_app stops its solver's group
        if pending:
            ray.wait(pending, num_returns=len(pending), timeout=2.0 * TERMINATE_GRACE_S + 5.0)
        time.sleep(0.1)
        raise
