import { useState } from "react";
import type { User, UserChange } from "../../api/admin";
import { formatTime } from "../common/Status";
import { parseGroups } from "./UserCreateForm";

interface Props {
  user: User;
  isMe: boolean;
  busy: boolean;
  onSave: (username: string, change: UserChange) => void;
  onDelete: (user: User) => void;
  onToken: (user: User) => void;
}

function sameGroups(a: string[], b: string[]): boolean {
  return a.length === b.length && a.every((g, i) => g === b[i]);
}

/** One user, with groups, admin and disabled editable in place. */
export function UserRow({ user, isMe, busy, onSave, onDelete, onToken }: Props) {
  const [groups, setGroups] = useState(user.groups.join(", "));
  const [isAdmin, setIsAdmin] = useState(user.is_admin);
  const [disabled, setDisabled] = useState(user.disabled);

  const change: UserChange = {};
  if (!sameGroups(parseGroups(groups), user.groups)) change.groups = parseGroups(groups);
  if (isAdmin !== user.is_admin) change.is_admin = isAdmin;
  if (disabled !== user.disabled) change.disabled = disabled;
  const changed = Object.keys(change).length > 0;

  return (
    <tr className={changed ? "row-changed" : undefined}>
      <td>
        {user.username}
        {isMe && <span className="badge">you</span>}
      </td>
      <td>
        <input aria-label={`Groups of ${user.username}`} value={groups} onChange={(e) => setGroups(e.target.value)} />
      </td>
      <td>
        <input type="checkbox" aria-label={`${user.username} is an admin`} checked={isAdmin} onChange={(e) => setIsAdmin(e.target.checked)} />
      </td>
      <td>
        <input type="checkbox" aria-label={`${user.username} is disabled`} checked={disabled} onChange={(e) => setDisabled(e.target.checked)} />
      </td>
      <td>{formatTime(user.created)}</td>
      <td className="row-actions">
        {changed && (
          <button type="button" disabled={busy} onClick={() => onSave(user.username, change)}>
            Save
          </button>
        )}
        <button type="button" disabled={busy} onClick={() => onToken(user)}>
          Token…
        </button>
        <button type="button" className="danger" disabled={busy} onClick={() => onDelete(user)}>
          Delete
        </button>
      </td>
    </tr>
  );
}
