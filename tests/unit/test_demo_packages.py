"""The demo is no part of the product: twinlink runs without its packages (`twinlink demo` then
says how to install them), and the crane's services stand apart from twinlink."""

from __future__ import annotations

import subprocess
import sys

import pytest
from click.testing import CliRunner

from twinlink.cli import main

DEMO_PACKAGES = ("twinlink_demo", "ilmatar_crane")


def _imported_after(code: str) -> set[str]:
    """The top-level modules a fresh interpreter has imported after running `code`."""
    probe = f"{code}\nimport sys\nprint(' '.join(sorted({{m.split('.')[0] for m in sys.modules}})))"
    out = subprocess.run(
        [sys.executable, "-c", probe], capture_output=True, text=True, timeout=120, check=True
    )
    return set(out.stdout.split())


def test_the_product_imports_no_demo_package() -> None:
    imported = _imported_after(
        "import twinlink.app, twinlink.server, twinlink.cli\n"
        "from twinlink.cli import main\n"
        "main(['--help'], standalone_mode=False)\n"
    )
    assert "twinlink" in imported  # the probe ran
    assert not imported & set(DEMO_PACKAGES)


def test_the_crane_services_import_nothing_of_twinlink() -> None:
    imported = _imported_after("import ilmatar_crane, ilmatar_crane.__main__")
    assert "ilmatar_crane" in imported
    assert not {"twinlink", "twinlink_edge", "twinlink_demo"} & imported


@pytest.mark.parametrize("missing", DEMO_PACKAGES)
def test_demo_without_its_packages_says_how_to_install_them(
    missing: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    # None in sys.modules: an import of it fails as if it were not installed.
    for name in [m for m in sys.modules if m.split(".")[0] in DEMO_PACKAGES]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, missing, None)
    result = CliRunner().invoke(main, ["demo", "--port", "0"])
    assert result.exit_code == 1, result.output
    assert result.exception is None or isinstance(result.exception, SystemExit)
    assert f"the demo is not installed (no module {missing})" in result.output
    assert "pip install -e examples/ilmatar -e examples/demo" in result.output
    assert "Traceback" not in result.output
