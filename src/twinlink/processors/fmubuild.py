"""Build FMUs from C sources, reproducibly.

A source folder holds a ``modelDescription.xml`` (FMI 2.0 or 3.0) and the C files of the model.
`build_fmu` compiles every ``*.c`` in it into one shared library with gcc, against the official
FMI headers that FMPy ships (``fmpy/c-code``), and zips the FMU:

    modelDescription.xml
    binaries/linux64/<modelIdentifier>.so        (FMI 2.0)
    binaries/x86_64-linux/<modelIdentifier>.so   (FMI 3.0)
    sources/*.c, sources/*.h

The same sources give the same bytes: the compiler runs in the source folder on relative file
names with the folder prefixes mapped away and ``SOURCE_DATE_EPOCH`` fixed, and the zip has
sorted entries, a fixed date (1980-01-01), fixed permissions and deflate compression.

Headers in the folder are packed into ``sources/`` too; a header shared between FMUs can be a
symbolic link in each folder (it is read through the link), so ``sources/`` is self-contained.

Command line::

    python -m twinlink.processors.fmubuild SOURCE_DIR OUT.fmu [--if-stale]
"""

from __future__ import annotations

import argparse
import importlib.util
import logging
import os
import platform
import re
import shutil
import stat
import subprocess
import sys
import tempfile
import zipfile
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from xml.etree import ElementTree

from twinlink.domain.errors import TwinlinkError

__all__ = ["FmuBuildError", "ModelInfo", "build_fmu", "build_if_stale", "main", "read_model_info"]

log = logging.getLogger(__name__)

#: The date of every zip entry: the earliest a zip file can hold.
ZIP_DATE_TIME = (1980, 1, 1, 0, 0, 0)
#: ``SOURCE_DATE_EPOCH`` for the compiler (1980-01-01T00:00:00Z), should a source use __DATE__.
SOURCE_DATE_EPOCH = "315532800"
FILE_MODE = 0o644
LIBRARY_MODE = 0o755
CFLAGS = ("-shared", "-fPIC", "-O2", "-std=c99", "-Wall", "-Wextra", "-frandom-seed=fmubuild")
LIBS = ("-lm",)
COMPILE_TIMEOUT_S = 300.0

_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


class FmuBuildError(TwinlinkError):
    """The FMU could not be built. The message says why, with the compiler's output if any."""


@dataclass(frozen=True)
class ModelInfo:
    """What the build needs from ``modelDescription.xml``."""

    fmi_version: str  # "2.0" or "3.0"
    model_identifier: str


def read_model_info(source_dir: Path) -> ModelInfo:
    """The FMI version and the model identifier of the FMU in `source_dir`."""
    path = source_dir / "modelDescription.xml"
    try:
        root = ElementTree.parse(path).getroot()
    except FileNotFoundError as err:
        raise FmuBuildError(f"{path} does not exist") from err
    except (OSError, ElementTree.ParseError) as exc:
        raise FmuBuildError(f"cannot read {path}: {exc}") from exc
    if root.tag != "fmiModelDescription":
        raise FmuBuildError(f"{path}: the root element is <{root.tag}>, not <fmiModelDescription>")
    version = root.get("fmiVersion", "")
    if version not in ("2.0", "3.0"):
        raise FmuBuildError(f'{path}: fmiVersion "{version}" is not supported (only 2.0 and 3.0)')
    identifiers = {
        element.get("modelIdentifier", "")
        for element in root
        if element.tag in ("CoSimulation", "ModelExchange")
    }
    if not identifiers:
        raise FmuBuildError(f"{path}: neither <CoSimulation> nor <ModelExchange> is declared")
    if len(identifiers) > 1:
        names = ", ".join(sorted(identifiers))
        raise FmuBuildError(
            f"{path}: the interfaces name different modelIdentifiers ({names}); "
            "this builder makes one binary, so they must be the same"
        )
    (identifier,) = identifiers
    if not _IDENTIFIER.fullmatch(identifier):
        raise FmuBuildError(f'{path}: modelIdentifier "{identifier}" is not a valid C identifier')
    return ModelInfo(fmi_version=version, model_identifier=identifier)


def fmi_headers_dir() -> Path:
    """The folder of the FMI headers that FMPy ships (found without importing FMPy)."""
    spec = importlib.util.find_spec("fmpy")
    if spec is None or spec.origin is None:
        raise FmuBuildError("FMPy is not installed; it provides the FMI headers (pip install fmpy)")
    headers = Path(spec.origin).parent / "c-code"
    if not (headers / "fmi2Functions.h").is_file():
        raise FmuBuildError(f"the FMI headers are missing from {headers}")
    return headers


def binary_dir(fmi_version: str) -> str:
    """The folder under ``binaries/`` for this machine, as FMI `fmi_version` names it."""
    if not sys.platform.startswith("linux"):
        raise FmuBuildError(f"building FMUs is only supported on Linux, not on {sys.platform}")
    machine = platform.machine().lower()
    architectures = {
        "x86_64": "x86_64",
        "amd64": "x86_64",
        "aarch64": "aarch64",
        "arm64": "aarch64",
    }
    if machine not in architectures:
        raise FmuBuildError(f"building FMUs is not supported on the {machine} architecture")
    if fmi_version == "2.0":
        return "linux64"
    return f"{architectures[machine]}-linux"


def _source_files(source_dir: Path) -> list[Path]:
    """The files of the folder that go into ``sources/``: ``*.c`` and ``*.h``, sorted."""
    return sorted(
        path for path in source_dir.iterdir() if path.suffix in (".c", ".h") and path.is_file()
    )


def _compile(
    source_dir: Path,
    sources: Sequence[str],
    library: Path,
    *,
    compiler: str,
    extra_cflags: Sequence[str],
) -> None:
    executable = shutil.which(compiler)
    if executable is None:
        raise FmuBuildError(
            f"the C compiler {compiler!r} was not found; install it to build FMUs "
            "(Debian/Ubuntu: apt-get install gcc)"
        )
    headers = fmi_headers_dir()
    command = [
        executable,
        *CFLAGS,
        f"-I{headers}",
        f"-I{source_dir}",
        # No absolute path of this machine may end up in the binary.
        f"-ffile-prefix-map={source_dir}=.",
        f"-ffile-prefix-map={headers}=fmi",
        f"-fdebug-prefix-map={source_dir}=.",
        f"-fdebug-prefix-map={headers}=fmi",
        *extra_cflags,
        *sources,
        "-o",
        str(library),
        *LIBS,
    ]
    env = {**os.environ, "LC_ALL": "C", "SOURCE_DATE_EPOCH": SOURCE_DATE_EPOCH}
    try:
        result = subprocess.run(
            command,
            cwd=source_dir,
            env=env,
            capture_output=True,
            text=True,
            errors="replace",
            timeout=COMPILE_TIMEOUT_S,
            check=False,
        )
    except FileNotFoundError as exc:
        raise FmuBuildError(
            f"the C compiler {compiler!r} could not be run ({exc}); install it to build FMUs "
            "(Debian/Ubuntu: apt-get install gcc)"
        ) from exc
    except subprocess.TimeoutExpired as exc:
        raise FmuBuildError(f"{compiler} took longer than {exc.timeout:g} s; gave up") from exc
    if result.returncode != 0:
        output = (result.stderr + result.stdout).strip()
        raise FmuBuildError(
            f"{compiler} failed (exit status {result.returncode}) building {source_dir}:\n{output}"
        )
    if result.stderr.strip():
        log.warning("%s warnings building %s:\n%s", compiler, source_dir, result.stderr.strip())


def _write_zip(out: Path, entries: dict[str, bytes]) -> None:
    """Write the zip to a temporary file beside `out`, then move it into place."""
    out.parent.mkdir(parents=True, exist_ok=True)
    fd, name = tempfile.mkstemp(prefix=f".{out.name}.", suffix=".tmp", dir=out.parent)
    tmp = Path(name)
    try:
        with os.fdopen(fd, "wb") as fh, zipfile.ZipFile(fh, "w") as zf:
            for arcname in sorted(entries):
                info = zipfile.ZipInfo(arcname, date_time=ZIP_DATE_TIME)
                info.compress_type = zipfile.ZIP_DEFLATED
                info.create_system = 3  # Unix, so the permissions below are read
                mode = LIBRARY_MODE if arcname.startswith("binaries/") else FILE_MODE
                info.external_attr = (stat.S_IFREG | mode) << 16
                zf.writestr(info, entries[arcname], compresslevel=9)
        tmp.chmod(FILE_MODE)
        tmp.replace(out)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def build_fmu(
    source_dir: Path,
    out: Path,
    *,
    compiler: str = "gcc",
    extra_cflags: Sequence[str] = (),
) -> Path:
    """Compile the FMU in `source_dir` and write it to `out`; returns `out`.

    `extra_cflags` go to the compiler after the standard flags (e.g. ``["-Werror"]``).
    Raises `FmuBuildError` when the model description is unusable, the compiler is missing
    or the compilation fails (the message holds the compiler's output).
    """
    source_dir = Path(source_dir).resolve()
    out = Path(out)
    if not source_dir.is_dir():
        raise FmuBuildError(f"{source_dir} is not a folder")
    info = read_model_info(source_dir)
    platform_folder = binary_dir(info.fmi_version)
    files = _source_files(source_dir)
    c_files = [path.name for path in files if path.suffix == ".c"]
    if not c_files:
        raise FmuBuildError(f"{source_dir} holds no *.c files")

    with tempfile.TemporaryDirectory(prefix="fmubuild-") as build_dir:
        library = Path(build_dir) / f"{info.model_identifier}.so"
        _compile(source_dir, c_files, library, compiler=compiler, extra_cflags=extra_cflags)
        binary = library.read_bytes()

    entries = {
        "modelDescription.xml": (source_dir / "modelDescription.xml").read_bytes(),
        f"binaries/{platform_folder}/{info.model_identifier}.so": binary,
    }
    for path in files:
        entries[f"sources/{path.name}"] = path.read_bytes()
    _write_zip(out, entries)
    return out


def _newest_input_ns(source_dir: Path) -> int:
    """The latest modification time among the files of `source_dir` (links and their targets)."""
    newest = 0
    for path in Path(source_dir).iterdir():
        if path.is_file():
            newest = max(newest, path.stat().st_mtime_ns, path.lstat().st_mtime_ns)
    return newest


def build_if_stale(
    source_dir: Path,
    out: Path,
    *,
    compiler: str = "gcc",
    extra_cflags: Sequence[str] = (),
) -> Path:
    """Build like `build_fmu`, but only when `out` is missing or a source file is newer."""
    source_dir = Path(source_dir)
    out = Path(out)
    if not source_dir.is_dir():
        raise FmuBuildError(f"{source_dir} is not a folder")
    if out.is_file() and _newest_input_ns(source_dir) <= out.stat().st_mtime_ns:
        return out
    return build_fmu(source_dir, out, compiler=compiler, extra_cflags=extra_cflags)


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m twinlink.processors.fmubuild",
        description="Build an FMU from a folder with modelDescription.xml and C sources.",
    )
    parser.add_argument("source_dir", type=Path, help="folder with modelDescription.xml and *.c")
    parser.add_argument("out", type=Path, help="the .fmu file to write")
    parser.add_argument(
        "--if-stale",
        action="store_true",
        help="only build when OUT is missing or older than a file in SOURCE_DIR",
    )
    args = parser.parse_args(argv)
    build = build_if_stale if args.if_stale else build_fmu
    try:
        path = build(args.source_dir, args.out)
    except FmuBuildError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    print(path)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
