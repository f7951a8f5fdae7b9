"""Which unfinished runs a starting node takes for its own dead ones: with a shared store,
only those of a node of this host whose process has ended (store/leases.py's node names,
`host:pid:random`); another host's, a live node's and a name of another shape are not."""

from __future__ import annotations

import os
import socket
import subprocess

from twinlink.store.leases import node_gone


def test_only_a_dead_node_of_this_host_is_gone() -> None:
    host = socket.gethostname()
    dead = subprocess.Popen(["true"])
    dead.wait()
    assert node_gone(f"{host}:{dead.pid}:abcd1234")
    assert not node_gone(f"{host}:{os.getpid()}:abcd1234")  # this very process
    assert not node_gone(f"other-{host}:{dead.pid}:abcd1234")
    assert not node_gone(f"{host}:not-a-pid:abcd1234")
    assert not node_gone("node-a")
