import type { Me } from "../../api/types";
import { formatTime } from "../common/Status";

/** Who the caller is. */
export function AccountSection({ me }: { me: Me }) {
  return (
    <dl className="props">
      <dt>Username</dt>
      <dd>{me.username}</dd>
      <dt>Groups</dt>
      <dd>{me.groups.length ? me.groups.join(", ") : <span className="muted">none</span>}</dd>
      <dt>Admin</dt>
      <dd>{me.is_admin ? "yes: you may see and change everything" : "no"}</dd>
      {me.created && (
        <>
          <dt>Since</dt>
          <dd>{formatTime(me.created)}</dd>
        </>
      )}
    </dl>
  );
}
