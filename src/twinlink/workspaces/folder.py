"""A workspace's folder and the environment its JupyterLab and kernels run in.

`data_dir/workspaces/<user>/` is the folder JupyterLab shows and its HOME; the user's files
stay there between starts. `library/` is made again at each start (library.py).
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

README = """\
# Your twinlink workspace

This JupyterLab runs on the twinlink server, as a process of its own, and only you can reach
it (through the platform, at /workspaces/{user}/). Your files here are kept when it stops.

- `library/<kind>/<name>/` holds the latest version of each asset of your private library
  space (`user:{user}`), copied here when the workspace first started with it: change them
  freely, they are your copies (delete one to get the latest version at the next start).
  `library/common/<kind>/<name>/` shows the `common` library, read-only, renewed at each
  start.
- Nothing here goes back to the library by itself. Push a changed folder as a new version
  (it becomes `latest`):

  ```python
  from twinlink.client import Client

  client = Client()  # TWINLINK_URL and TWINLINK_TOKEN are set in this workspace
  client.library.push("library/models/my-model", kind="models", name="my-model")
  ```

  or in a terminal: `twinlink lib push --help`.
- `TWINLINK_TOKEN` is an API token of yours made for this workspace; it is revoked when the
  workspace stops. The workspace stops after a while without use (the server's
  TWINLINK_WORKSPACE_IDLE_S); start it again from the app.
"""


def prepare(root: Path, username: str) -> None:
    """The folder, made if missing, with this README written again (it says how things
    are now)."""
    root.mkdir(parents=True, exist_ok=True, mode=0o700)
    (root / "README.md").write_text(README.format(user=username), encoding="utf-8")


def environment(root: Path, server_url: str, token: str) -> dict[str, str]:
    """Everything JupyterLab and its kernels see of the world: nothing of the server's
    environment (it may hold the first admin's password, the store's URL, the vault key)
    but where programs and the language are, and how to reach the platform as the user."""
    bin_dir = str(Path(sys.executable).parent)  # python, jupyter and twinlink of this install
    return {
        "PATH": os.pathsep.join((bin_dir, "/usr/local/bin", "/usr/bin", "/bin")),
        "HOME": str(root),
        "LANG": os.environ.get("LANG", "C.UTF-8"),
        "SHELL": "/bin/bash" if Path("/bin/bash").exists() else "/bin/sh",
        "TERM": "xterm-256color",
        "TWINLINK_URL": server_url,
        "TWINLINK_TOKEN": token,
    }
