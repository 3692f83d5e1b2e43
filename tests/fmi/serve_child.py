"""Run ``vessel-gym serve SCENARIO --allow-code --duration S`` in this process with a listen-only viewer
socket; print JSON: the states it received (sim time, wall time of arrival) and how many FMU instances the
importer made (tests/fmi/test_serve_fmu.py)."""

from __future__ import annotations

import json
import socket
import sys
import threading
import time

from vessel_gym import cli
from vessel_gym.fmi import component

made = []
_instance = component.FmuSlot._instance


def counted(self, k):
    made.append((k, id(self)))
    return _instance(self, k)


component.FmuSlot._instance = counted
sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
sock.bind(("127.0.0.1", 0))
sock.settimeout(0.2)
states = []
done = threading.Event()


def receive():
    while not done.is_set():
        try:
            data = sock.recv(65536)
        except OSError:
            continue
        msg = json.loads(data)
        if msg.get("type") == "state":
            states.append((msg["t_s"], time.monotonic(), msg["rpm"]))


threading.Thread(target=receive, daemon=True).start()
scenario, duration = sys.argv[1], sys.argv[2]
view = f"127.0.0.1:{sock.getsockname()[1]}"
flags = f"--allow-code --duration {duration} --nmea off --view {view} --json 127.0.0.1:0 --seed 0"
rc = cli.main(["serve", scenario, *flags.split()])
done.set()
print("RESULT " + json.dumps({"rc": rc, "instances": made, "states": states}))
