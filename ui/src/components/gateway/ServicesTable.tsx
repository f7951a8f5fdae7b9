import type { Service, ServiceStats } from "../../api/types";
import { HealthBadge } from "./HealthBadge";

/** Answers by status class: "2xx 120 · 4xx 3 · 5xx 1". */
export function statusClasses(stats: ServiceStats | undefined): [string, number][] {
  const classes = new Map<string, number>();
  for (const [status, count] of Object.entries(stats?.statuses ?? {})) {
    const key = `${status[0]}xx`;
    classes.set(key, (classes.get(key) ?? 0) + count);
  }
  return [...classes.entries()].sort();
}

function latency(stats: ServiceStats | undefined): string {
  const ms = stats?.upstream_ms;
  if (!ms) return "—";
  const p95 = ms.p95 === null ? "> 10 s" : `≤ ${ms.p95} ms`;
  return `${ms.mean.toFixed(1)} ms (p95 ${p95})`;
}

/** One twin's gateway services: health, where they are, credentials, answers and latency. */
export function ServicesTable({ services }: { services: Service[] }) {
  return (
    <div className="table-scroll">
      <table className="table">
        <thead>
          <tr>
            <th>Service</th>
            <th>Health</th>
            <th>Base URL</th>
            <th>Credentials</th>
            <th className="num">Requests</th>
            <th>Answers</th>
            <th>Service time</th>
          </tr>
        </thead>
        <tbody>
          {services.map((s) => (
            <tr key={s.name}>
              <td className="mono">{s.name}</td>
              <td>
                <HealthBadge service={s} />
                {s.health?.ms !== undefined && <span className="muted"> {s.health.ms} ms</span>}
              </td>
              <td className="mono">{s.base_url}</td>
              <td>
                {s.auth.method}
                {s.credential_error && <span className="badge badge-bad" title={s.credential_error}>error</span>}
                {s.blocked && <span className="badge badge-bad" title={s.blocked}>blocked</span>}
              </td>
              <td className="num">{s.requests}</td>
              <td>
                {statusClasses(s.stats).map(([cls, n]) => (
                  <span key={cls} className={`badge ${cls === "2xx" || cls === "3xx" ? "badge-ok" : "badge-bad"}`}>
                    {cls} {n}
                  </span>
                ))}
              </td>
              <td>{latency(s.stats)}</td>
            </tr>
          ))}
        </tbody>
      </table>
    </div>
  );
}
