import type { TokenInfo } from "../../api/admin";
import { formatTime } from "../common/Status";

interface RowProps {
  token: TokenInfo;
  showUser: boolean;
  busy: boolean;
  onRevoke: (t: TokenInfo) => void;
}

function TokenRow({ token: t, showUser, busy, onRevoke }: RowProps) {
  return (
    <tr className={t.current ? "token-current" : undefined}>
      {showUser && <td>{t.username}</td>}
      <td>
        {t.name}
        {t.current && <span className="badge">this session</span>}
      </td>
      <td>{t.kind}</td>
      <td>
        <span className={`badge token-state-${t.state}`}>{t.state}</span>
      </td>
      <td className="mono">{t.prefix}…</td>
      <td>{formatTime(t.created)}</td>
      <td>{t.expires ? formatTime(t.expires) : "never"}</td>
      <td>{formatTime(t.last_used)}</td>
      <td>
        {t.state === "active" && (
          // The server marks the token this tab signed in with: revoking it signs you out.
          <button
            type="button"
            className="danger"
            disabled={busy}
            title={t.current ? "This session's token: revoking it signs you out" : undefined}
            onClick={() => onRevoke(t)}
          >
            {t.current ? "Revoke and sign out" : "Revoke"}
          </button>
        )}
      </td>
    </tr>
  );
}

interface Props {
  tokens: TokenInfo[];
  /** Add a column with the user each token belongs to (every user's tokens). */
  showUser?: boolean;
  busy: boolean;
  onRevoke: (t: TokenInfo) => void;
}

/** Tokens as the server lists them: never with their secrets. */
export function TokenTable({ tokens, showUser = false, busy, onRevoke }: Props) {
  return (
    <table className="table" data-testid="token-table">
      <thead>
        <tr>
          {showUser && <th>User</th>}
          <th>Name</th>
          <th>Kind</th>
          <th>State</th>
          <th>Prefix</th>
          <th>Created</th>
          <th>Expires</th>
          <th>Last used</th>
          <th aria-label="Actions" />
        </tr>
      </thead>
      <tbody>
        {tokens.map((t) => (
          <TokenRow key={t.id} token={t} showUser={showUser} busy={busy} onRevoke={onRevoke} />
        ))}
      </tbody>
    </table>
  );
}
