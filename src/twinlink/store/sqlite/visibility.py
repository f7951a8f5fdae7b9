"""The SQL form of the privacy rules in twinlink.auth.rights, for filtering in the database."""

from __future__ import annotations

from twinlink.domain.records import Visibility


def part_visible(vis: Visibility, twin_col: str, privacy_col: str) -> tuple[str, list[object]]:
    """A WHERE fragment true when the reader may see the part (`twin_col`, `privacy_col`).

    public: everyone. private: the twin's owners and editors. Any other level (a group):
    anyone with a role on the twin, and members of the user group of that name.
    """
    if vis.is_admin:
        return "1", []
    clauses = [f"{privacy_col} = 'public'"]
    args: list[object] = []
    if vis.groups:
        # A user group named like a fixed level grants nothing: "private" is never a group.
        clauses.append(
            f"({privacy_col} IN ({', '.join('?' * len(vis.groups))})"
            f" AND {privacy_col} NOT IN ('public', 'private'))"
        )
        args.extend(vis.groups)
    if vis.user_id is not None:
        clauses.append(
            f"EXISTS (SELECT 1 FROM twin_roles r WHERE r.twin_id = {twin_col} AND r.user_id = ?"
            f" AND ({privacy_col} <> 'private' OR r.role IN ('owner', 'editor')))"
        )
        args.append(vis.user_id)
    return "(" + " OR ".join(clauses) + ")", args


def visible_private_parts(vis: Visibility) -> tuple[str, list[object]]:
    """A SELECT of the search_parts ids that are not public and that the reader may see: the
    same rules as part_visible, written to start from the reader's groups and roles (a few
    index lookups) instead of testing every part."""
    selects: list[str] = []
    args: list[object] = []
    if vis.groups:
        marks = ", ".join("?" * len(vis.groups))
        selects.append(
            f"SELECT p.id FROM search_parts p WHERE p.privacy IN ({marks})"
            " AND p.privacy NOT IN ('public', 'private')"
        )
        args.extend(vis.groups)
    if vis.user_id is not None:
        selects.append(
            "SELECT p.id FROM twin_roles r JOIN search_parts p ON p.twin_id = r.twin_id"
            " WHERE r.user_id = ? AND p.privacy <> 'public'"
            " AND (p.privacy <> 'private' OR r.role IN ('owner', 'editor'))"
        )
        args.append(vis.user_id)
    if not selects:
        return "SELECT NULL WHERE 0", []
    return " UNION ALL ".join(selects), args
