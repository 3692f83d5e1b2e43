"""The classroom: students steer ships of one harbour from a browser, an instructor watches, sets the weather
and ends the class with a debrief (``vessel-gym classroom SCENARIO``; docs/classroom.md).

:mod:`.harbour` the ships simulated together (and what each hears of the others over AIS), :mod:`.agents` the
ships a trained agent steers, :mod:`.codes` the class's codes, :mod:`.server` the page, the websocket and their
gate, :mod:`.scene3d` the student's 3D scene, :mod:`.debrief` the class debrief, :mod:`.command` the command line.
"""

#: own ships in one class: the issue's class size, and what the page's chart and the step budget are sized for
MAX_SHIPS = 16
