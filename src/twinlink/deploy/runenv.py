"""The environment a lifecycle run sees (docs/runs.md): built from nothing, so none of the
server's own environment (its settings, TWINLINK_SECRET_KEY, the store's URL) reaches a
script that a package brought."""

from __future__ import annotations

import json
import re
import sys
from collections.abc import Mapping
from pathlib import Path
from typing import Any

# The platform's interpreter first (its `python3` has the twinlink client and CLI), then the
# system's usual places.
RUN_PATH = f"{Path(sys.executable).parent}:/usr/local/bin:/usr/bin:/bin"
_NOT_NAME = re.compile(r"[^A-Z0-9_]")


def env_name(name: str) -> str:
    """A parameter's or device's name as part of a variable's name: upper case, anything but
    letters, digits and `_` as `_` (`tingen-SAP` -> `TINGEN_SAP`)."""
    return _NOT_NAME.sub("_", name.upper())


def param_text(value: Any) -> str:
    """A parameter's value as a variable holds it: a string as it is, anything else as JSON
    (`0.7`, `true`, `[1, 2]`)."""
    return value if isinstance(value, str) else json.dumps(value)


def run_environment(
    *,
    work: Path,
    url: str,
    token: str,
    twin: str,
    deployment: str,
    phase: str,
    run_id: int,
    params: Mapping[str, Any],
    device_tokens: Mapping[str, str],
) -> dict[str, str]:
    env = {
        "PATH": RUN_PATH,
        "HOME": str(work),
        "LANG": "C.UTF-8",
        "TWINLINK_URL": url,
        "TWINLINK_TOKEN": token,
        "TWINLINK_TWIN": twin,
        "TWINLINK_DEPLOYMENT": deployment,
        "TWINLINK_PHASE": phase,
        "TWINLINK_RUN_ID": str(run_id),
        "TWINLINK_PARAMS": json.dumps(dict(params)),
    }
    for name, value in params.items():
        env[f"TWINLINK_PARAM_{env_name(name)}"] = param_text(value)
    for device, device_token in device_tokens.items():
        env[f"TWINLINK_DEVICE_TOKEN_{env_name(device)}"] = device_token
    return env
