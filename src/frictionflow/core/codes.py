"""How a kernel run ended: one set of status codes for every engine.

Each kernel returns one of these; the façades turn them into results or
one-line errors.  Not every engine can end every way (only the adaptive
solver has a step cap, only the flow maps can miss their section), but a
code means the same thing wherever it is returned.
"""

from __future__ import annotations

#: the run reached its end (or an early-stop rule ended it)
OK = 0
#: an output buffer was too short: the façade reruns with more room
FULL = 1
#: repeated zero-length phases: the switch model cannot continue (a sliding motion it cannot represent)
STUCK = 2
#: the adaptive step cap was reached
STEP_CAP = 3
#: the adaptive step fell below its floor
TINY_STEP = 4
#: a flow map did not return to its section
NO_RETURN = 5
#: a flow map's step failed
STEP_FAIL = 6
#: the state left the floating-point range
NOT_FINITE = 7
#: a contact's normal load reached 0 (a structure with state-dependent normal loads): the run stops there
CONTACT_LOST = 8

NAMES = {OK: "ok", FULL: "full", STUCK: "stuck", STEP_CAP: "step cap", TINY_STEP: "tiny step",
         NO_RETURN: "no return", STEP_FAIL: "step failed", NOT_FINITE: "not finite",
         CONTACT_LOST: "contact lost"}
