"""``vessel-cfd run --ray``: the independent cases as Ray tasks on a local Ray instance.

The mesh and the base tow run in this process through :class:`FakeFoam`; the Ray tasks run in Ray's
worker processes, where :class:`HereFoam` hands over to the real :func:`cfd.runner.run_app`, which starts
real programs: ``simpleFoam`` and ``pimpleFoam`` on PATH are small scripts that run the same
:class:`FakeFoam` in the case folder. So the tasks go through the real process handling (and its stop on
Ctrl-C), and the results must equal those of a local run exactly.
"""

from __future__ import annotations

import io
import os
import signal
import stat
import sys
import threading
import time
from pathlib import Path

import pytest
from cfd_fake_foam import FakeFoam, fake_environment
from test_cfd_pipeline import DATA, study

from cfd import raycases, runner
from cfd.cli import main
from cfd.errors import CfdError
from cfd.pipeline import DONE, Pipeline
from cfd.runner import Progress

ray = pytest.importorskip("ray")
TESTS = Path(__file__).resolve().parent
ROOT = TESTS.parents[1]
SOLVER = """#!{python}
import importlib.util, os, sys, time
from pathlib import Path
# the fake solver's module by its path (it is a test helper, not a package); cfd comes with vessel-gym
spec = importlib.util.spec_from_file_location("cfd_fake_foam", {fake!r})
fake = importlib.util.module_from_spec(spec)
spec.loader.exec_module(fake)
FakeFoam = fake.FakeFoam
case = Path.cwd()
hang = case.parent.parent / "hang_in"  # names the case being solved when Ctrl-C comes
if hang.is_file() and hang.read_text() == case.name:
    (case.parent.parent / "solver.pid").write_text(str(os.getpid()))
    time.sleep(120)
fail = case.parent.parent / "fail_in"  # names a case whose solver crashes
if fail.is_file() and fail.read_text() == case.name:
    print("--> FOAM FATAL ERROR: ")
    print("stand-in crash for the test")
    sys.exit(3)
FakeFoam()([{app!r}], case, {app!r})
"""


class HereFoam(FakeFoam):
    """The fake in this process; in any other (a Ray worker it was sent to) the real run_app."""

    def __init__(self) -> None:
        super().__init__()
        self.pid = os.getpid()

    def __call__(self, argv, case, step, **kw):
        if os.getpid() == self.pid:
            return super().__call__(argv, case, step, **kw)
        return runner.run_app(argv, case, step, **kw)


@pytest.fixture(scope="module")
def local_ray(tmp_path_factory):
    bindir = tmp_path_factory.mktemp("bin")
    for app in ("simpleFoam", "pimpleFoam"):
        script = bindir / app
        script.write_text(SOLVER.format(python=sys.executable, fake=str(TESTS / "cfd_fake_foam.py"), app=app))
        script.chmod(script.stat().st_mode | stat.S_IEXEC)
    path = f"{bindir}{os.pathsep}{os.environ.get('PATH', '')}"
    # 2 Ray CPUs (a resource count, not cores) so that the case that hangs does not hold back the others
    pythonpath = os.pathsep.join([str(TESTS), str(ROOT), os.environ.get("PYTHONPATH", "")])
    env = {"PATH": path, "PYTHONPATH": pythonpath}
    sigterm = signal.getsignal(signal.SIGTERM)  # ray.init replaces it with an exit
    ray.init(num_cpus=2, include_dashboard=False, runtime_env={"env_vars": env})
    yield bindir
    ray.shutdown()
    signal.signal(signal.SIGTERM, sigterm)


@pytest.fixture(autouse=True)
def _plain_signals():
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)  # Ray's driver installs its own
    runner.STOP.clear()
    yield
    runner.STOP.clear()
    signal.signal(signal.SIGINT, previous)


def test_ray_tasks_give_the_local_results_and_a_rerun_skips_them(tmp_path, monkeypatch, local_ray):
    local = study(tmp_path / "local")
    fake_environment(monkeypatch, FakeFoam())
    expected = Pipeline(local, Progress(quiet=True), plots=False).run().derivatives

    s = study(tmp_path / "ray")
    fake = fake_environment(monkeypatch, HereFoam())
    stream = io.StringIO()
    got = Pipeline(s, Progress(stream), plots=False, ray="local").run().derivatives
    here = {name for app, name in fake.calls if app.endswith("Foam")}
    assert here == {"tow_U1.0000"}  # the base tow ran here, every other case as a Ray task
    cases = sorted(p.name for p in (s.out / "cases").iterdir() if p.is_dir())
    assert all((s.out / "cases" / c / DONE).is_file() for c in cases) and len(cases) == 9
    assert set(got) == set(expected)
    for key, value in expected.items():
        assert got[key] == pytest.approx(value, rel=1e-12, abs=1e-15), key
    text = stream.getvalue()
    assert "sent to Ray" in text and "case 9 of 9 finished" in text

    again = io.StringIO()
    Pipeline(s, Progress(again), plots=False, ray="local").run()
    assert again.getvalue().count("already done") == 9 and "sent to Ray" not in again.getvalue()


def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as fh:
            return fh.read().split()[2] not in "ZX"
    except FileNotFoundError:
        return False


def test_ctrl_c_cancels_the_tasks_stops_the_solver_and_keeps_finished_cases(tmp_path, monkeypatch, local_ray):
    s = study(tmp_path, tests="drift", speeds="1.0", drift_deg="3,6,9")
    fake_environment(monkeypatch, HereFoam())
    s.out.mkdir(parents=True)
    (s.out / "hang_in").write_text("drift_b06.00")  # read by the stand-in solver in the Ray worker
    pidfile = s.out / "solver.pid"

    def interrupt() -> None:  # Ctrl-C once the case hangs and the two others have finished
        end = time.monotonic() + 60
        cases = s.out / "cases"
        while time.monotonic() < end:
            done = all((cases / c / DONE).is_file() for c in ("drift_b03.00", "drift_b09.00"))
            if pidfile.is_file() and done:
                break
            time.sleep(0.1)
        os.kill(os.getpid(), signal.SIGINT)

    threading.Thread(target=interrupt, daemon=True).start()
    with pytest.raises(KeyboardInterrupt):
        Pipeline(s, Progress(quiet=True), plots=False, ray="local").run()
    pid = int(pidfile.read_text())
    end = time.monotonic() + 15
    while _alive(pid) and time.monotonic() < end:
        time.sleep(0.1)
    assert not _alive(pid)  # the cancelled task stopped its solver
    cases = s.out / "cases"
    assert (cases / "drift_b03.00" / DONE).is_file() and (cases / "drift_b09.00" / DONE).is_file()
    assert not (cases / "drift_b06.00" / DONE).exists()

    fake = fake_environment(monkeypatch, FakeFoam())  # a local rerun resumes: only the stopped case runs
    runner.STOP.clear()
    Pipeline(s, Progress(quiet=True), plots=False).run()
    assert {name for app, name in fake.calls if app == "simpleFoam"} == {"drift_b06.00"}


def test_a_failed_task_reports_the_case_error_as_a_local_run_does(tmp_path, monkeypatch, local_ray):
    s = study(tmp_path, tests="drift", speeds="1.0", drift_deg="3,6")
    fake_environment(monkeypatch, HereFoam())
    s.out.mkdir(parents=True)
    (s.out / "fail_in").write_text("drift_b06.00")
    with pytest.raises(CfdError) as err:
        Pipeline(s, Progress(quiet=True), plots=False, ray="local").run()
    text = str(err.value)
    assert "simpleFoam (drift beta=6 deg)" in text and "exited with code 3" in text and "FOAM FATAL" in text


def test_an_unreachable_ray_address_is_one_line_and_exit_2(tmp_path, monkeypatch, capsys):
    def refuse(**kw):
        raise ConnectionError("could not find any running Ray instance")

    fake_environment(monkeypatch, HereFoam())
    monkeypatch.setattr(
        raycases,
        "_ray",
        lambda: type("R", (), {"is_initialized": staticmethod(lambda: False), "init": staticmethod(refuse)}),
    )
    args = ["run", "--hull", "wigley", "--lpp", "1", "--bwl", "0.1", "--tm", "0.0625", "--tests", "drift"]
    args += ["--out", str(tmp_path / "out"), "--template", str(DATA / "small_ship.toml"), "--scale-to", "cfd"]
    assert main([*args, "--ray", "nowhere:6379"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [
        "vessel-cfd: error: ray: cannot connect to the Ray cluster at 'nowhere:6379': "
        "could not find any running Ray instance"
    ]


def test_joining_ray_keeps_the_signal_handlers_that_stop_the_solvers(monkeypatch):
    def init(**kw):  # as ray.init does: SIGTERM would exit the process without stopping the solvers
        signal.signal(signal.SIGTERM, lambda signum, frame: sys.exit(signum))

    fake_ray = type(
        "R",
        (),
        {
            "is_initialized": staticmethod(lambda: False),
            "init": staticmethod(init),
            "cluster_resources": staticmethod(lambda: {"CPU": 3.0}),
        },
    )
    monkeypatch.setattr(raycases, "_ray", lambda: fake_ray)

    def as_ctrl_c(signum, frame):
        raise KeyboardInterrupt

    previous = signal.signal(signal.SIGTERM, as_ctrl_c)
    try:
        assert raycases.connect("local", 1) == 3
        assert signal.getsignal(signal.SIGTERM) is as_ctrl_c
    finally:
        signal.signal(signal.SIGTERM, previous)
