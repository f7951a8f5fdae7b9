"""Which nodes that left co-simulations `running` are gone, on a store nodes share: a node
(store/leases.py's `host:pid:random`) of this host whose process has ended. Another host's
nodes are that host's to judge (deploy/recovery.py judges the lifecycle runs' the same way)."""

from __future__ import annotations

import os
import socket


def gone_nodes(nodes: list[str]) -> list[str]:
    return sorted({node for node in nodes if _gone(node)})


def _gone(node: str) -> bool:
    host, _, rest = node.partition(":")
    pid = rest.partition(":")[0]
    if host != socket.gethostname() or not pid.isdigit():
        return False
    try:
        os.kill(int(pid), 0)
    except ProcessLookupError:
        return True
    except PermissionError:  # alive, another user's
        return False
    return False
