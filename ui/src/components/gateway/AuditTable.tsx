import { Link } from "react-router-dom";
import type { AuditEntry } from "../../api/types";
import { Empty } from "../common/Status";
import { formatClock, formatEpochMs } from "../common/time";

function ms(value: number | null): string {
  return value === null || value === undefined ? "—" : value.toFixed(1);
}

export function AuditTable({ entries }: { entries: AuditEntry[] }) {
  if (entries.length === 0) return <Empty>No requests have passed the gateway yet. Try a service from a twin's page.</Empty>;
  return (
    <div className="table-scroll">
      <table className="table">
        <thead>
          <tr>
            <th>Time</th>
            <th>Status</th>
            <th>Method</th>
            <th>Twin / service</th>
            <th>Path</th>
            <th>Caller</th>
            <th className="num">Total ms</th>
            <th className="num">Upstream ms</th>
          </tr>
        </thead>
        <tbody>
          {entries.map((e) => (
            <tr key={e.id}>
              <td title={formatEpochMs(e.time * 1000)}>{formatClock(e.time * 1000)}</td>
              <td>
                <span className={e.status < 400 ? "status status-ok" : "status status-bad"} title={e.outcome}>
                  {e.status}
                </span>
                {e.outcome !== "forwarded" && <span className="muted"> {e.outcome}</span>}
              </td>
              <td>{e.method}</td>
              <td>
                <Link to={`/twins/${encodeURIComponent(e.twin)}`}>{e.twin}</Link> / {e.service}
              </td>
              <td className="mono">{e.path}</td>
              <td>{e.caller}</td>
              <td className="num">{ms(e.total_ms)}</td>
              <td className="num">{ms(e.upstream_ms)}</td>
            </tr>
          ))}
        </tbody>
      </table>
    </div>
  );
}
