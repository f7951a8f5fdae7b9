import { useState, type FormEvent } from "react";
import type { NewUser } from "../../api/admin";

/** Group names typed as "group-1, group-2" (commas or spaces). */
export function parseGroups(text: string): string[] {
  return text
    .split(/[\s,]+/)
    .map((g) => g.trim())
    .filter(Boolean);
}

/** A new user: username, an optional password, groups and the admin flag. */
export function UserCreateForm({ busy, onCreate }: { busy: boolean; onCreate: (user: NewUser) => Promise<boolean> }) {
  const [username, setUsername] = useState("");
  const [password, setPassword] = useState("");
  const [groups, setGroups] = useState("");
  const [isAdmin, setIsAdmin] = useState(false);
  const shortPassword = password.length > 0 && password.length < 8;

  async function submit(event: FormEvent) {
    event.preventDefault();
    const user: NewUser = { username: username.trim(), is_admin: isAdmin, groups: parseGroups(groups) };
    if (password) user.password = password;
    if (await onCreate(user)) {
      setUsername("");
      setPassword("");
      setGroups("");
      setIsAdmin(false);
    }
  }

  return (
    <form className="inline-form" onSubmit={(e) => void submit(e)} aria-label="Create a user">
      <label>
        Username
        <input value={username} maxLength={64} onChange={(e) => setUsername(e.target.value)} autoComplete="off" />
      </label>
      <label>
        Password (optional)
        <input type="password" value={password} onChange={(e) => setPassword(e.target.value)} autoComplete="new-password" />
      </label>
      <label>
        Groups
        <input value={groups} onChange={(e) => setGroups(e.target.value)} placeholder="group-1, group-2" />
      </label>
      <label className="check">
        <input type="checkbox" checked={isAdmin} onChange={(e) => setIsAdmin(e.target.checked)} /> Admin
      </label>
      <button type="submit" disabled={busy || !username.trim() || shortPassword}>
        Create user
      </button>
      {shortPassword && <span className="muted">A password needs at least 8 characters.</span>}
      {!password && username && <span className="muted">Without a password the user cannot sign in; give them a token instead.</span>}
    </form>
  );
}
