"""The twinlink demo, which `twinlink demo` (and so `make demo`) runs: the server with the
example twins, the simulated Tingen rig and its FMU, and the Ilmatar crane's services behind
the gateway. It is no part of the product: a package of its own, installed by `make setup`."""

from twinlink_demo.run import serve_demo

__all__ = ["serve_demo"]
