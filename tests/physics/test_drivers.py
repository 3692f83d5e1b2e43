"""The per-call choice between the serial and the threaded batch driver (physics.drivers._DriverChoice), driven
by made-up call times: the logic is checked without timing anything (both drivers give bitwise identical
results, tests/physics/test_sanity.py and test_setup_scaling.py; the choice changes timing only)."""

from __future__ import annotations

from vessel_gym.physics.drivers import (
    DRIVER_THREADED_MARGIN,
    DRIVER_TRIAL_COST,
    DRIVER_TRIAL_EVERY,
    _DriverChoice,
)

WORK = 1024  # vessel-steps per call
US = 1e-6  # s


def run(choice: _DriverChoice, calls: int, cost_us) -> tuple[list[int], float]:
    """``calls`` calls through ``choice``; ``cost_us(driver, i)`` is the time per vessel-step (us) of call i with
    that driver (a fake clock). Returns the drivers picked and the total time (s)."""
    picks, total = [], 0.0
    for i in range(calls):
        d = choice.pick()
        seconds = cost_us(d, i) * US * WORK
        choice.record(d, seconds, WORK)
        picks.append(d)
        total += seconds
    return picks, total


def trial_gaps(picks: list[int], tried: int) -> list[int]:
    """Calls between successive picks of the driver ``tried``."""
    at = [i for i, d in enumerate(picks) if d == tried]
    return [b - a for a, b in zip(at, at[1:])]


def test_first_calls_time_each_driver_once_after_a_warm_up_call():
    picks, _ = run(_DriverChoice(), 4, lambda d, i: 1.0)
    assert picks == [1, 1, 0, 0]  # threaded: warm-up (not timed), timed; then serial alike


def test_a_driver_that_keeps_losing_its_trials_is_tried_ever_more_rarely():
    # a busy second core: the threaded driver loses every trial by 10 %, which alone would keep the trial
    # interval at its least (cost ratio 1.1 -> (1.1 - 1) / DRIVER_TRIAL_COST = 5 calls, raised to 8)
    choice = _DriverChoice()
    picks, _ = run(choice, 6000, lambda d, i: 1.1 if d else 1.0)
    gaps = trial_gaps(picks[4:], tried=1)
    lo, hi = DRIVER_TRIAL_EVERY
    assert gaps[:4] == [2 * lo, 4 * lo, 8 * lo, 16 * lo]  # doubled after each lost trial
    assert max(gaps) == hi and gaps[-3:] == [hi, hi, hi]  # up to the cap
    assert choice.best() == 0


def test_a_won_trial_resets_the_interval_and_the_faster_driver_takes_over():
    choice = _DriverChoice()
    run(choice, 3000, lambda d, i: 1.1 if d else 1.0)  # threaded backed off to the longest interval
    assert choice.every == DRIVER_TRIAL_EVERY[1]
    # the other process ends: two cores give the threaded driver 0.55 us per vessel-step
    picks, _ = run(choice, 2 * DRIVER_TRIAL_EVERY[1] + 50, lambda d, i: 0.55 if d else 1.0)
    first = picks.index(1)
    assert first <= DRIVER_TRIAL_EVERY[1]  # tried within the interval it had reached
    assert choice.best() == 1
    after = picks[picks.index(1, first + 1) :]  # from the second won trial on: threaded is the choice
    assert sum(after) >= 0.98 * len(after)  # serial tried now and then
    gaps = trial_gaps(after, tried=0)  # serial now loses its trials, and backs off
    assert len(gaps) >= 3 and all(1.9 * a <= b <= 2.1 * a for a, b in zip(gaps, gaps[1:]))


def test_trials_cost_at_most_the_stated_fraction_when_threads_lose():
    # threaded 3 x slower (both cores busy): the trials add at most DRIVER_TRIAL_COST to the serial-only time
    choice = _DriverChoice()
    n = 20000
    picks, total = run(choice, n, lambda d, i: 3.0 if d else 1.0)
    serial_only = n * 1.0 * US * WORK
    first_timings = 2 * (3.0 - 1.0) * US * WORK  # the two threaded calls at the start
    assert total - first_timings <= (1.0 + DRIVER_TRIAL_COST) * serial_only


def test_threaded_is_chosen_only_when_cheaper_by_the_margin():
    choice = _DriverChoice()
    choice.cost, choice.warm = [1.0 * US, (1.0 - 0.5 * DRIVER_THREADED_MARGIN) * US], [True, True]
    assert choice.best() == 0  # within the margin: serial (one core, no wait for a second one)
    choice.cost[1] = (1.0 - 2.0 * DRIVER_THREADED_MARGIN) * US
    assert choice.best() == 1


def test_a_single_descheduled_call_does_not_flip_the_choice():
    choice = _DriverChoice()
    run(choice, 200, lambda d, i: 0.5 if d else 1.0)  # idle machine: threaded
    assert choice.best() == 1
    picks, _ = run(choice, 3, lambda d, i: 50.0 if i == 0 else 0.5)  # one call waited 100 x for a core
    assert picks == [1, 1, 1]
