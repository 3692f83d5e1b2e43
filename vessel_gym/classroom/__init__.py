"""The classroom: students steer ships of one harbour from a browser, an instructor watches, sets the weather
and ends the class with a debrief (``vessel-gym classroom SCENARIO``; docs/classroom.md).

:mod:`.harbour` the ships simulated together, :mod:`.codes` the class's codes, :mod:`.server` the page, the
websocket and their gate, :mod:`.debrief` the class debrief, :mod:`.command` the command line.
"""

#: own ships in one class: the issue's class size, and what the page's chart and the step budget are sized for
MAX_SHIPS = 16
