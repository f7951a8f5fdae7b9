"""Simulated devices: the NTNU thesis's cantilever rig ("Tingen") and a generic signal source.

They are devices like any other, clients of this SDK and nothing of the server, so they live
here: `twinlink simulate` runs them (it makes the device token first), the demo runs the rig,
and a machine with only twinlink-edge installed can run them too (`runner.run_tingen`).
The models (`tingen.py`, `generic.py`) are pure, with no I/O; `runner.py` connects them to a
server through the SDK.
"""
