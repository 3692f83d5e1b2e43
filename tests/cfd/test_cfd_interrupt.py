"""Ctrl-C and SIGTERM: running applications are stopped with their whole process group, finished cases
are kept and a rerun resumes; progress counts the cases and gives an ETA."""

from __future__ import annotations

import io
import os
import signal
import threading
import time

import pytest
from cfd_fake_foam import FakeFoam, fake_environment
from test_cfd_pipeline import DATA, study
from test_cfd_runner import _script, bindir  # noqa: F401 - the fixture

from cfd import runner
from cfd.pipeline import DONE, Pipeline
from cfd.runner import Progress, Stopped, run_app, stop_all


@pytest.fixture(autouse=True)
def _clear_stop():
    # Ctrl-C is Python's default SIGINT handler (KeyboardInterrupt in the main thread), as in a terminal; a
    # library loaded by an earlier test in this process (Ray installs its own) may have replaced it
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    runner.STOP.clear()
    yield
    runner.STOP.clear()
    signal.signal(signal.SIGINT, previous)


def _alive(pid: int, within_s: float = 3.0) -> bool:
    """Whether ``pid`` still runs after up to ``within_s`` (a signalled process takes a moment to go)."""
    end = time.monotonic() + within_s
    while True:
        try:
            with open(f"/proc/{pid}/stat") as fh:
                if fh.read().split()[2] in "ZX":  # a zombie is dead too
                    return False
        except FileNotFoundError:
            return False
        if time.monotonic() > end:
            return True
        time.sleep(0.05)


def _solver_with_child(bindir, tmp_path):  # noqa: F811
    # the "solver" starts a child (as mpirun starts its ranks), writes both pids, then runs for a minute
    _script(
        bindir, "pimpleFoam", f"sleep 60 &\necho $! > {tmp_path}/child\necho $$ > {tmp_path}/parent\nwait\n"
    )


def _pids(tmp_path):
    for _ in range(100):
        if (tmp_path / "child").is_file() and (tmp_path / "parent").is_file():
            return int((tmp_path / "parent").read_text()), int((tmp_path / "child").read_text())
        time.sleep(0.05)
    raise AssertionError("the stand-in solver did not start")


def test_stop_all_terminates_the_process_group_of_a_solver_in_another_thread(tmp_path, bindir):  # noqa: F811
    _solver_with_child(bindir, tmp_path)
    errors = []

    def solve():
        try:
            run_app(["pimpleFoam"], tmp_path, "pimpleFoam (sway)")
        except Stopped as exc:
            errors.append(exc)

    worker = threading.Thread(target=solve)
    worker.start()
    parent, child = _pids(tmp_path)
    stop_all()
    worker.join(timeout=10)
    assert not worker.is_alive() and errors and "interrupted" in str(errors[0])
    assert not _alive(parent) and not _alive(child)
    with pytest.raises(Stopped, match="not started"):  # nothing new starts once stopped
        run_app(["pimpleFoam"], tmp_path, "pimpleFoam (yaw)")


def test_ctrl_c_in_the_waiting_thread_terminates_the_process_group(tmp_path, bindir):  # noqa: F811
    _solver_with_child(bindir, tmp_path)

    def interrupt():  # called by run_app's wait loop, where a Ctrl-C would land
        if (tmp_path / "child").is_file():
            raise KeyboardInterrupt

    t0 = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        run_app(["pimpleFoam"], tmp_path, "pimpleFoam (sway)", on_tick=interrupt)
    parent, child = _pids(tmp_path)
    assert not _alive(parent) and not _alive(child) and time.monotonic() - t0 < 30


class _InterruptedFoam(FakeFoam):
    """Sends ``signum`` to this process when the solver of case ``at`` starts, then runs until stopped."""

    def __init__(self, at: str, signum: int) -> None:
        super().__init__()
        self.at, self.signum = at, signum

    def __call__(self, argv, case, step, **kw):
        if case.name == self.at and argv[0].endswith("Foam"):
            os.kill(os.getpid(), self.signum)
            for _ in range(200):
                if runner.STOP.is_set():
                    raise Stopped(step, "stopped")
                time.sleep(0.05)
            raise AssertionError("the pipeline did not stop the running solver")
        return super().__call__(argv, case, step, **kw)


def test_sigterm_keeps_finished_cases_and_a_rerun_resumes(tmp_path, monkeypatch, capsys):
    from cfd.cli import main

    s = study(tmp_path, tests="drift", speeds="1.0", drift_deg="3,6,9")
    args = ["run", "--hull", "wigley", "--lpp", "1", "--bwl", "0.1", "--tm", "0.0625", "--tests", "drift"]
    args += ["--speeds", "1.0", "--pmm-speed", "1.0", "--drift-deg", "3,6,9", "--rho", "1000", "--nu", "1e-6"]
    args += ["--out", str(s.out), "--template", str(DATA / "small_ship.toml"), "--scale-to", "cfd"]
    fake_environment(monkeypatch, _InterruptedFoam("drift_b06.00", signal.SIGTERM))
    assert main(args) == 130
    err = capsys.readouterr().err
    assert "interrupted; running solvers stopped, finished cases kept" in err
    assert "case 1 of 5 started" in err and "case 3 of 5 finished" in err and "ETA" in err
    cases = s.out / "cases"
    assert (cases / "mesh" / DONE).is_file() and (cases / "drift_b03.00" / DONE).is_file()
    assert not (cases / "drift_b06.00" / DONE).exists() and not (s.out / "ship.toml").exists()

    fake = fake_environment(monkeypatch, FakeFoam())
    stream = io.StringIO()
    Pipeline(s, Progress(stream), plots=False).run()
    solved = {name for app, name in fake.calls if app == "simpleFoam"}
    assert solved == {"drift_b06.00", "drift_b09.00"}  # the finished cases were kept
    assert stream.getvalue().count("already done") == 3


def test_ctrl_c_stops_cases_running_side_by_side(tmp_path, monkeypatch):
    fake_environment(monkeypatch, _InterruptedFoam("drift_b06.00", signal.SIGINT))
    s = study(tmp_path, tests="drift", speeds="1.0", drift_deg="3,6,9", procs=2)
    with pytest.raises(KeyboardInterrupt):
        Pipeline(s, Progress(quiet=True), plots=False).run()
    assert runner.STOP.is_set()
