import { useState, type FormEvent } from "react";
import { listRoles, removeRole, ROLE_NAMES, setRole, type RoleGrant, type RoleName } from "../../api/admin";
import type { Twin } from "../../api/types";
import { useApi } from "../../hooks/useApi";
import { useAction } from "../admin/useAction";
import { Empty, ErrorMessage, Loading } from "../common/Status";
import "../admin/admin.css";

function RoleSelect({ value, disabled, label, onChange }: { value: RoleName; disabled: boolean; label: string; onChange: (r: RoleName) => void }) {
  return (
    <select aria-label={label} value={value} disabled={disabled} onChange={(e) => onChange(e.target.value as RoleName)}>
      {ROLE_NAMES.map((r) => (
        <option key={r}>{r}</option>
      ))}
    </select>
  );
}

function GrantForm({ busy, onGrant }: { busy: boolean; onGrant: (username: string, role: RoleName) => Promise<boolean> }) {
  const [username, setUsername] = useState("");
  const [role, setRoleValue] = useState<RoleName>("viewer");

  async function submit(event: FormEvent) {
    event.preventDefault();
    if (username.trim() && (await onGrant(username.trim(), role))) setUsername("");
  }

  return (
    <form className="inline-form" onSubmit={(e) => void submit(e)} aria-label="Grant a role">
      <label>
        Username
        <input value={username} onChange={(e) => setUsername(e.target.value)} placeholder="carol" />
      </label>
      <label>
        Role
        <RoleSelect value={role} disabled={busy} label="New role" onChange={setRoleValue} />
      </label>
      <button type="submit" disabled={busy || !username.trim()}>
        Grant
      </button>
    </form>
  );
}

function RoleTable({ roles, busy, onChange, onRemove }: { roles: RoleGrant[]; busy: boolean; onChange: (u: string, r: RoleName) => void; onRemove: (u: string) => void }) {
  return (
    <table className="table">
      <thead>
        <tr>
          <th>User</th>
          <th>Role</th>
          <th aria-label="Actions" />
        </tr>
      </thead>
      <tbody>
        {roles.map((r) => (
          <tr key={r.username}>
            <td>{r.username}</td>
            <td>
              <RoleSelect value={r.role} disabled={busy} label={`Role of ${r.username}`} onChange={(role) => onChange(r.username, role)} />
            </td>
            <td>
              <button type="button" className="danger" disabled={busy} onClick={() => onRemove(r.username)}>
                Remove
              </button>
            </td>
          </tr>
        ))}
      </tbody>
    </table>
  );
}

/** Who has which role on the twin; owners (and admins) grant, change and take roles away.
 * Shows nothing to other callers: their role is in the overview's first line. */
export function RolesSection({ slug, role }: { slug: string; role: Twin["role"] }) {
  if (role !== "owner" && role !== "admin") return null;
  return <RolesManager slug={slug} />;
}

function RolesManager({ slug }: { slug: string }) {
  const roles = useApi((signal) => listRoles(slug, signal), [slug]);
  const action = useAction();

  const grant = (username: string, role: RoleName) =>
    action.run(async () => {
      await setRole(slug, username, role);
      roles.reload();
    });
  const remove = (username: string) => {
    if (!window.confirm(`Take ${username}'s role on this twin away?`)) return;
    void action.run(async () => {
      await removeRole(slug, username);
      roles.reload();
    });
  };

  return (
    <>
      <h2>Roles</h2>
      <p className="muted section-note">Owners manage roles; editors change the twin and its devices and send commands; viewers read it.</p>
      {action.error && <ErrorMessage error={action.error} />}
      {roles.error ? (
        <ErrorMessage error={roles.error} onRetry={roles.reload} />
      ) : !roles.data ? (
        <Loading />
      ) : roles.data.length === 0 ? (
        <Empty>Nobody has a role on this twin.</Empty>
      ) : (
        <RoleTable roles={roles.data} busy={action.busy} onChange={(u, r) => void grant(u, r)} onRemove={remove} />
      )}
      <GrantForm busy={action.busy} onGrant={grant} />
    </>
  );
}
