import type { TokenInfo } from "../../api/admin";
import { getToken } from "../../api/client";
import { formatTime } from "../common/Status";

/** Whether a listed token is the one this browser tab signed in with (by its prefix). */
export function isThisSession(token: TokenInfo): boolean {
  const own = getToken();
  return own !== null && token.prefix.length > 0 && own.startsWith(token.prefix);
}

function TokenRow({ token: t, busy, onRevoke }: { token: TokenInfo; busy: boolean; onRevoke: (t: TokenInfo) => void }) {
  return (
    <tr>
      <td>
        {t.name}
        {isThisSession(t) && <span className="badge">this session</span>}
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
          <button type="button" className="danger" disabled={busy} onClick={() => onRevoke(t)}>
            Revoke
          </button>
        )}
      </td>
    </tr>
  );
}

/** Tokens as the server lists them: never with their secrets. */
export function TokenTable({ tokens, busy, onRevoke }: { tokens: TokenInfo[]; busy: boolean; onRevoke: (t: TokenInfo) => void }) {
  return (
    <table className="table" data-testid="token-table">
      <thead>
        <tr>
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
          <TokenRow key={t.id} token={t} busy={busy} onRevoke={onRevoke} />
        ))}
      </tbody>
    </table>
  );
}
