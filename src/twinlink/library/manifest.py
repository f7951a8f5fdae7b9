"""What a library version is: its files (`FileEntry`, a domain record: path, content digest,
size, executable bit), the digest of that list, and the rules every file path obeys however
it arrived."""

from __future__ import annotations

import hashlib
import re
from collections.abc import Iterable
from dataclasses import dataclass

from twinlink.domain.errors import InvalidInputError
from twinlink.domain.library import FileEntry

# A path is written under a materialized version's folder by a runner and by workspaces:
# bounded so it stays a valid path there on any common file system.
MAX_PATH_BYTES = 1024
MAX_PART_BYTES = 255
_CONTROL = re.compile(r"[\x00-\x1f\x7f]")
_DRIVE = re.compile(r"^[A-Za-z]:")


@dataclass(frozen=True, slots=True)
class Limits:
    """What one push may hold: `max_bytes` both for the upload and for its unpacked total
    (counted on the bytes unpacked, not on what the archive's headers claim), and the
    number of entries of an archive (folders included)."""

    max_bytes: int
    max_files: int = 10_000


def version_digest(files: Iterable[FileEntry]) -> str:
    """`sha256:` + the SHA-256 of the canonical manifest: for the files sorted by path, the
    UTF-8 bytes of "path NUL sha256 NUL size NUL executable(0|1) LF" concatenated. Paths hold
    no control characters (`check_path`), so the separators cannot be forged."""
    digest = hashlib.sha256()
    for f in sorted(files, key=lambda f: f.path):
        digest.update(f"{f.path}\0{f.sha256}\0{f.size}\0{int(f.executable)}\n".encode())
    return "sha256:" + digest.hexdigest()


def check_path(raw: str, *, folder: bool = False) -> str:
    """The path of an archive entry as kept: '/'-separated, relative, without a leading
    './' (what `tar -C dir -cf x.tar .` writes). Refused with InvalidInputError naming the
    entry: absolute paths, '..', backslashes, control characters, empty parts, overlong
    names. A folder's path (`folder`) may end in '/' and be empty (the archive's root)."""
    parts = raw.split("/")
    while len(parts) > 1 and parts[0] == ".":
        parts.pop(0)
    if folder and parts[-1] == "":
        parts.pop()
    if folder and parts in ([], ["."]):
        return ""
    path = "/".join(parts)
    problem = _path_problem(raw, parts)
    if problem:
        raise InvalidInputError(f"entry {raw!r}: {problem}")
    return path


def _path_problem(raw: str, parts: list[str]) -> str | None:
    if not raw:
        return "an entry without a name"
    if raw.startswith("/") or _DRIVE.match(raw):
        return "an absolute path; paths in the archive must be relative to its root"
    if "\\" in raw:
        return "a backslash in the path; use '/' between folders"
    if _CONTROL.search(raw):
        return "a control character (NUL, newline, ...) in the path"
    if ".." in parts:
        return "the path goes up ('..'); paths must stay inside the archive's root"
    if "" in parts or "." in parts:
        return "an empty or '.' part in the path ('a//b', 'a/./b')"
    if len(raw.encode()) > MAX_PATH_BYTES:
        return f"the path is longer than {MAX_PATH_BYTES} bytes"
    if any(len(part.encode()) > MAX_PART_BYTES for part in parts):
        return f"a file or folder name is longer than {MAX_PART_BYTES} bytes"
    return None


def check_unique(paths: Iterable[str]) -> None:
    """Refuse a path given twice, and a file that is also the folder of another ('a' and
    'a/b'): the tree could not be written."""
    seen: set[str] = set()
    for path in paths:
        if path in seen:
            raise InvalidInputError(f"entry {path!r}: the archive holds it twice")
        seen.add(path)
    for path in seen:
        parts = path.split("/")
        for end in range(1, len(parts)):
            folder = "/".join(parts[:end])
            if folder in seen:
                raise InvalidInputError(
                    f"entry {path!r}: {folder!r} is a file in the archive, not a folder"
                )
