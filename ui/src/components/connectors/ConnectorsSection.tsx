import { connectorAction, listConnectors, type Connector, type ConnectorAction } from "../../api/connectors";
import { useApi } from "../../hooks/useApi";
import { useAction } from "../admin/useAction";
import { Empty, ErrorMessage, Loading } from "../common/Status";
import { formatEpochMs } from "../common/time";

const GOOD = new Set(["listening", "connected"]);
const BAD = new Set(["error", "reconnecting"]);

function StateBadge({ connector: c }: { connector: Connector }) {
  const state = c.enabled ? c.status.state : "disabled";
  const tone = GOOD.has(state) ? "badge badge-ok" : BAD.has(state) ? "badge badge-bad" : "badge";
  return <span className={tone}>{state}</span>;
}

function fromNs(ns: number | null): string {
  return ns === null ? "never" : formatEpochMs(ns / 1e6);
}

interface RowProps {
  connector: Connector;
  canManage: boolean;
  busy: boolean;
  onAction: (c: Connector, action: ConnectorAction) => void;
}

function ConnectorRow({ connector: c, canManage, busy, onAction }: RowProps) {
  const s = c.status;
  return (
    <tr>
      <td className="mono">{c.name}</td>
      <td>{c.kind}</td>
      <td className="mono">{c.device}</td>
      <td>
        <StateBadge connector={c} />
        {s.address && <span className="muted mono"> {s.address}</span>}
      </td>
      <td>{s.messages.toLocaleString()}</td>
      <td>{s.samples.toLocaleString()}</td>
      <td title={s.last_error ?? undefined}>
        {s.error_count > 0 ? (
          <>
            {s.error_count.toLocaleString()} <span className="muted">{s.last_error}</span>
          </>
        ) : (
          "0"
        )}
      </td>
      <td>{fromNs(s.last_message_ns)}</td>
      {canManage && (
        <td className="row-actions">
          {c.enabled ? (
            <>
              <button type="button" disabled={busy} onClick={() => onAction(c, "restart")}>
                Restart
              </button>
              <button type="button" disabled={busy} onClick={() => onAction(c, "stop")}>
                Stop
              </button>
            </>
          ) : (
            <button type="button" disabled={busy} onClick={() => onAction(c, "start")}>
              Start
            </button>
          )}
        </td>
      )}
    </tr>
  );
}

/** A twin's connectors (UDP datasources, OPC UA clients) with their state and figures;
 * admins start, stop and restart them. Creating one is done by API, CLI or `twinlink apply`. */
export function ConnectorsSection({ slug, canManage }: { slug: string; canManage: boolean }) {
  const connectors = useApi((signal) => listConnectors(slug, signal), [slug]);
  const action = useAction();
  const act = (c: Connector, what: ConnectorAction) =>
    void action.run(async () => {
      await connectorAction(slug, c.name, what);
      connectors.reload();
    });

  let body;
  if (connectors.error) body = <ErrorMessage error={connectors.error} onRetry={connectors.reload} />;
  else if (connectors.loading && !connectors.data) body = <Loading />;
  else if (!connectors.data || connectors.data.length === 0)
    body = (
      <Empty>
        No connectors. A device that cannot run the SDK (catman over UDP, a machine&apos;s OPC UA server) is
        connected by one, made by an admin with <code>twinlink connectors add</code> (docs/connectors.md).
      </Empty>
    );
  else
    body = (
      <table className="table">
        <thead>
          <tr>
            <th>Connector</th>
            <th>Kind</th>
            <th>Device</th>
            <th>State</th>
            <th>Messages</th>
            <th>Samples</th>
            <th>Errors</th>
            <th>Last message</th>
            {canManage && <th aria-label="Actions" />}
          </tr>
        </thead>
        <tbody>
          {connectors.data.map((c) => (
            <ConnectorRow key={c.name} connector={c} canManage={canManage} busy={action.busy} onAction={act} />
          ))}
        </tbody>
      </table>
    );
  return (
    <>
      <h2>Connectors</h2>
      {action.error && <ErrorMessage error={action.error} />}
      {body}
    </>
  );
}
