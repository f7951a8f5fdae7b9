"""The `twinlink` command: it runs the server (`up`, `demo`) and talks to a running one over
the API (every other command). root.py is the command and its list of commands; each other
module is one area of them; client.py is the API client they share."""

from twinlink.cli.root import main

__all__ = ["main"]
