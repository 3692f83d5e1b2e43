"""Classroom benchmark: key press to state echo, in a real browser, with a full class on loopback.

    python benchmarks/bench_classroom.py                 # 16 ships, then 2, each page view, about 4 min
    python benchmarks/bench_classroom.py --ships 16 --presses 40 --views both

For each class size, ``vessel-gym classroom harbour --ships N`` runs in its own process at time factor 1. The
instructor's code (printed by the command) gives the helm codes; N - 1 scripted students (websocket clients in
this process) join ships 2..N and each gives an order every 0.5 s, as people pressing keys do; one headless
Chromium joins ship 1 and presses the arrow keys ``--presses`` times, 0.25 s apart. The page itself times each
key press: from its keydown handler (``performance.now()``) to the state message that echoes that order's
sequence number (``window.vg.latencies``). Printed: median, p95 and largest of those and of the scripted
students' send-to-echo times. ``--views``: the page shows the chart and the 3D view side by side (``both``,
a laptop's default: the page's WebGL drawing shares the browser's main thread with the key handler) or the
chart only (``chart``); each view is a class of its own.

Goal (issue): key press to echo <= 100 ms at 16 ships on loopback.
"""

from __future__ import annotations

import argparse
import asyncio
import importlib.util
import json
import os
import re
import socket
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _chromium_driver():
    """The tests' headless-Chromium driver (tests/net/chromium.py), loaded from its file: a checkout's tests are
    not part of the installed package."""
    spec = importlib.util.spec_from_file_location("chromium_driver", ROOT / "tests" / "net" / "chromium.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _pct(xs: list[float], q: float) -> float:
    xs = sorted(xs)
    return xs[min(len(xs) - 1, int(round(q * (len(xs) - 1))))]


def _line(label: str, xs: list[float]) -> str:
    if not xs:
        return f"{label:34s} no samples"
    return (
        f"{label:34s} n={len(xs):4d}  median {statistics.median(xs):6.1f} ms  p95 {_pct(xs, 0.95):6.1f} ms  "
        f"max {max(xs):6.1f} ms"
    )


async def _join(url: str, origin: str, code: str, name: str):
    from websockets.asyncio.client import connect

    for _ in range(30):  # joins from one address are rate-limited: wait and try again
        ws = await connect(url, origin=origin, max_size=None)
        await ws.send(json.dumps({"type": "join", "code": code, "name": name}))
        while True:
            m = json.loads(await ws.recv())
            if m["type"] in ("welcome", "refused"):
                break
        if m["type"] == "welcome":
            return ws, m
        await ws.close()
        await asyncio.sleep(1.0)
    raise RuntimeError(f"{name}: could not join: {m}")


async def _codes(url: str, origin: str, instructor: str) -> list[str]:
    ws, _w = await _join(url, origin, instructor, "")
    while True:
        m = json.loads(await ws.recv())
        if m["type"] == "state" and "class" in m:
            await ws.close()
            return [s["code"] for s in m["class"]]


async def _student(
    url: str, origin: str, code: str, name: str, stop: asyncio.Event, out: list[float], joined: list[str]
) -> None:
    ws, w = await _join(url, origin, code, name)
    joined.append(name)
    sent: dict[int, float] = {}

    async def reader() -> None:
        async for raw in ws:
            m = json.loads(raw)
            ack = m.get("ack", -1)
            if ack in sent:
                out.append((time.perf_counter() - sent.pop(ack)) * 1e3)

    task = asyncio.ensure_future(reader())
    seq, rudder = 0, 0
    while not stop.is_set():
        seq += 1
        rudder = 5 if rudder <= 0 else -5
        sent[seq] = time.perf_counter()
        await ws.send(json.dumps({"type": "order", "session": w["session"], "seq": seq, "rudder": rudder,
                                  "telegraph": 1}))  # fmt: skip
        await asyncio.sleep(0.5)
    await ws.close()
    task.cancel()


def run_class(ships: int, presses: int, view: str = "both") -> dict[str, list[float]]:
    port = _free_port()
    out = tempfile.mkdtemp(prefix="vessel-gym-bench-classroom-")
    env = {**os.environ, "PYTHONPATH": f"{ROOT}{os.pathsep}{os.environ.get('PYTHONPATH', '')}"}
    cmd = [sys.executable, "-m", "vessel_gym.cli", "classroom", "harbour", "--ships", str(ships), "--bind",
           f"127.0.0.1:{port}", "--duration", "600", "--seed", "1", "--out", out]  # fmt: skip
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, text=True)
    origin, url = f"http://127.0.0.1:{port}", f"ws://127.0.0.1:{port}/ws"
    try:
        instructor = None
        deadline = time.monotonic() + 300
        while instructor is None:
            line = proc.stdout.readline()
            assert line and time.monotonic() < deadline, "the classroom did not start"
            found = re.search(r"instructor code (\S+)", line)
            instructor = found.group(1) if found else None
        codes = asyncio.run(_codes(url, origin, instructor))
        bots: list[float] = []
        joined: list[str] = []
        loop = asyncio.new_event_loop()
        stop = asyncio.Event()

        async def crowd() -> None:
            await asyncio.gather(
                *(
                    _student(url, origin, codes[k], f"bot {k + 1}", stop, bots, joined)
                    for k in range(1, ships)
                )
            )

        runner = threading.Thread(target=lambda: loop.run_until_complete(crowd()), daemon=True)
        runner.start()
        deadline = time.monotonic() + 60
        while len(joined) < ships - 1:  # joins from one address are rate-limited: the page joins last
            assert time.monotonic() < deadline, "the scripted students did not join"
            time.sleep(0.2)
        time.sleep(1.5)  # the join budget refilled
        with _chromium_driver().Chromium(1100, 800) as b:
            b.call("Page.navigate", url=origin + "/")
            for _ in range(300):
                b.pump(0.1)
                ready = b.call(
                    "Runtime.evaluate",
                    expression="document.readyState === 'complete' && typeof window.vg === 'object'",
                    returnByValue=True,
                )
                if ready.get("result", {}).get("value"):
                    break
            expr = (f"document.getElementById('code').value = {json.dumps(codes[0])};"
                    "document.getElementById('joinbtn').click(); true")  # fmt: skip
            b.call("Runtime.evaluate", expression=expr)
            for _ in range(300):
                b.pump(0.1)
                got = b.call(
                    "Runtime.evaluate", expression="window.vg && vg.state !== null", returnByValue=True
                )
                if got.get("result", {}).get("value"):
                    break
            b.call("Runtime.evaluate", expression=f"vg.view = {json.dumps(view)}; resize(); true")
            joined_page = b.call("Runtime.evaluate", expression="vg.role", returnByValue=True)["result"]
            if joined_page.get("value") != "helm":
                why = b.call(
                    "Runtime.evaluate",
                    expression="document.getElementById('joinmsg').innerText",
                    returnByValue=True,
                )
                raise RuntimeError(f"the page did not join: {why['result'].get('value')!r}")
            for i in range(presses):
                key = ("ArrowRight", 39) if i % 2 == 0 else ("ArrowLeft", 37)
                b.press(key[0], key[0], key[1])
                b.pump(0.25)
            b.pump(0.5)
            page = b.call("Runtime.evaluate", expression="vg.latencies", returnByValue=True)["result"][
                "value"
            ]
        loop.call_soon_threadsafe(stop.set)
        runner.join(10)
        return {"page": page, "bots": bots}
    finally:
        proc.terminate()
        proc.wait(30)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--ships", type=int, nargs="*", default=[16, 2])
    p.add_argument("--presses", type=int, default=40)
    p.add_argument("--views", nargs="*", choices=("both", "chart"), default=["both", "chart"])
    args = p.parse_args()
    if _chromium_driver().chromium_path() is None:
        sys.exit("bench_classroom: needs chromium (Debian package chromium)")
    print(
        f"key press to echo, loopback, {os.cpu_count()} CPUs (a shared machine: figures vary with its load)"
    )
    for n in args.ships:
        for view in args.views:
            got = run_class(n, args.presses, view)
            print(f"--- {n} ships, page view {view}")
            print(_line("browser key press -> echo", got["page"]))
            print(_line("scripted students send -> echo", got["bots"]))


if __name__ == "__main__":
    main()
