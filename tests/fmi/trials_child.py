"""Run the 35 deg turning circle, the 10/10 zig-zag and the crash stop of ship files in a process of their own and print their
results as JSON: ``python trials_child.py SHIP...`` (code from the ship files allowed).

The FMU engines of these ships run Python inside this process (pythonfmu); kept out of the test process so
that one FMU's fault cannot take the test run with it.
"""

from __future__ import annotations

import json
import sys


def main() -> None:
    from vessel_gym.manoeuvres.trials import stopping, turning_circle, zigzag
    from vessel_gym.physics.components import allow_code

    allow_code()
    out = {}
    for ship in sys.argv[1:]:
        tc = turning_circle(ship, 35.0)
        st = stopping(ship)
        zz = zigzag(ship, 10.0, 10.0)
        out[ship] = {"turning_circle": tc.to_dict(), "stopping": st.to_dict(), "zigzag": zz.to_dict()}
    print(json.dumps(out))


if __name__ == "__main__":
    main()
