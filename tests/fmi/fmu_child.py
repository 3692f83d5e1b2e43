"""Simulate FMUs with fmpy in a process of their own: ``python fmu_child.py runs.json out.npz``.

An FMU written with pythonfmu runs Python inside the host; with fmpy in a Python process, pythonfmu 0.7's
library aborts that process when it ends (glibc: "corrupted double-linked list", after every result is in).
The tests therefore run such FMUs here and end with ``os._exit`` once the results are written.

runs.json: a list of {"fmu", "stop_time", "step_size", "start_values", "output"}; out.npz: run<i>_<name>.
"""

from __future__ import annotations

import json
import os
import sys

import numpy as np


def main() -> None:
    import fmpy

    runs = json.loads(open(sys.argv[1], encoding="utf-8").read())
    out = {}
    for i, run in enumerate(runs):
        res = fmpy.simulate_fmu(
            run["fmu"],
            start_time=0.0,
            stop_time=run["stop_time"],
            step_size=run["step_size"],
            output_interval=run["step_size"],
            start_values=run.get("start_values", {}),
            output=run["output"],
        )
        for name in res.dtype.names:
            out[f"run{i}_{name}"] = np.asarray(res[name], dtype=float)
    np.savez(sys.argv[2], **out)


if __name__ == "__main__":
    code = 0
    try:
        main()
    except BaseException as exc:  # noqa: BLE001 - reported to the test, then the process ends at once
        print(f"{type(exc).__name__}: {exc}", file=sys.stderr, flush=True)
        code = 1
    sys.stdout.flush()
    os._exit(code)
