"""Write the API description without a server: `python -m twinlink.openapi [FILE]`.

The web app's types are generated from it (`make ui-types`, ui/scripts/api-types.mjs). It
builds the app as `twinlink up` would, so it sits beside the composition root (`app.py`),
not in `api/`, which the app is built from.
"""

from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path

from twinlink.api.contract import describe
from twinlink.app import create_app
from twinlink.config import Settings


def write(path: Path | None) -> None:
    """Write the description of an app built with default settings in a scratch data dir;
    nothing is started (no lifespan), so no server, port or store is needed."""
    with tempfile.TemporaryDirectory() as scratch:
        spec = describe(create_app(Settings(data_dir=Path(scratch))))
    text = json.dumps(spec, indent=2, sort_keys=False) + "\n"
    if path is None:
        sys.stdout.write(text)
    else:
        path.write_text(text, encoding="utf-8")


if __name__ == "__main__":
    write(Path(sys.argv[1]) if len(sys.argv) > 1 else None)
