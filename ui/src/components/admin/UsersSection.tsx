import { useState } from "react";
import {
  createTokenFor,
  createUser,
  deleteUser,
  listUsers,
  updateUser,
  type IssuedToken,
  type NewToken,
  type NewUser,
  type User,
  type UserChange,
} from "../../api/admin";
import { useApi } from "../../hooks/useApi";
import { Empty, ErrorMessage, Loading } from "../common/Status";
import { CreateTokenForm } from "./CreateTokenForm";
import { SecretOnce } from "./SecretOnce";
import { UserCreateForm } from "./UserCreateForm";
import { UserRow } from "./UserRow";
import { useAction } from "./useAction";

function UserTable({ users, me, ...handlers }: { users: User[]; me: string } & Omit<Parameters<typeof UserRow>[0], "user" | "isMe">) {
  return (
    <table className="table">
      <thead>
        <tr>
          <th>User</th>
          <th>Groups</th>
          <th>Admin</th>
          <th>Disabled</th>
          <th>Created</th>
          <th aria-label="Actions" />
        </tr>
      </thead>
      <tbody>
        {users.map((u) => (
          // Keyed by the stored values too, so a row starts afresh after a save.
          <UserRow key={`${u.username}:${u.groups.join(",")}:${u.is_admin}:${u.disabled}`} user={u} isMe={u.username === me} {...handlers} />
        ))}
      </tbody>
    </table>
  );
}

/** All users (admins): create, change groups, admin and disabled, delete, and give a user a token. */
export function UsersSection({ me }: { me: string }) {
  const users = useApi((signal) => listUsers(signal), []);
  const [tokenFor, setTokenFor] = useState<User>();
  const [issued, setIssued] = useState<IssuedToken>();
  const action = useAction();

  // Each change reloads the list, so the table shows what the server stored.
  const change = (fn: () => Promise<unknown>) =>
    action.run(async () => {
      await fn();
      users.reload();
    });
  const create = (user: NewUser) => change(() => createUser(user));
  const save = (username: string, userChange: UserChange) => void change(() => updateUser(username, userChange));
  const remove = (user: User) => {
    if (!window.confirm(`Delete the user ${user.username}? Their tokens and roles are deleted with them.`)) return;
    void change(() => deleteUser(user.username));
  };
  const issue = (username: string, token: NewToken) =>
    action.run(async () => {
      setIssued(await createTokenFor(username, token));
      setTokenFor(undefined);
    });

  return (
    <>
      {issued && (
        <SecretOnce title={`New token "${issued.name}" of ${issued.username ?? "the user"}`} secret={issued.token} onDone={() => setIssued(undefined)} />
      )}
      {action.error && <ErrorMessage error={action.error} />}
      {users.error ? (
        <ErrorMessage error={users.error} onRetry={users.reload} />
      ) : !users.data ? (
        <Loading />
      ) : users.data.length === 0 ? (
        <Empty>No users.</Empty>
      ) : (
        <UserTable users={users.data} me={me} busy={action.busy} onSave={save} onDelete={remove} onToken={setTokenFor} />
      )}
      {tokenFor && (
        <div className="card">
          <strong>A token for {tokenFor.username}</strong> <span className="muted">(it acts with their rights)</span>
          <CreateTokenForm busy={action.busy} label={`Create a token for ${tokenFor.username}`} onCreate={(t) => issue(tokenFor.username, t)} />
          <button type="button" className="link-button" onClick={() => setTokenFor(undefined)}>
            Cancel
          </button>
        </div>
      )}
      <h3>Create a user</h3>
      <UserCreateForm busy={action.busy} onCreate={create} />
    </>
  );
}
