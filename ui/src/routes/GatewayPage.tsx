import { useEffect } from "react";
import { Link } from "react-router-dom";
import { listAudit, listServices } from "../api/gateway";
import { listTwins } from "../api/twins";
import type { Service } from "../api/types";
import { useAuth } from "../auth/AuthContext";
import { Empty, ErrorMessage, Loading } from "../components/common/Status";
import { AuditTable } from "../components/gateway/AuditTable";
import { HealthBadge } from "../components/gateway/HealthBadge";
import { useApi } from "../hooks/useApi";

export const AUDIT_REFRESH_MS = 5000;

/** Each twin's services; twins the user may not list services of are left out. */
async function servicesByTwin(signal: AbortSignal): Promise<{ slug: string; name: string; services: Service[] }[]> {
  const page = await listTwins(null, 100, signal);
  const all = await Promise.all(
    page.items.map(async (twin) => {
      try {
        return { slug: twin.slug, name: twin.name, services: await listServices(twin.slug, signal) };
      } catch {
        return { slug: twin.slug, name: twin.name, services: [] };
      }
    }),
  );
  return all.filter((t) => t.services.length > 0);
}

function AuditSection() {
  const audit = useApi((signal) => listAudit(100, signal), []);
  const { reload } = audit;
  useEffect(() => {
    const timer = setInterval(reload, AUDIT_REFRESH_MS);
    return () => clearInterval(timer);
  }, [reload]);
  if (audit.error && !audit.data) return <ErrorMessage error={audit.error} />;
  if (!audit.data) return <Loading />;
  return (
    <>
      {audit.error && <ErrorMessage error={audit.error} />}
      <AuditTable entries={audit.data} />
    </>
  );
}

export function GatewayPage() {
  const { me } = useAuth();
  const twins = useApi(servicesByTwin, []);

  return (
    <main className="page">
      <h1>Gateway</h1>
      <h2>Recent requests</h2>
      <p className="muted">The newest 100 requests, refreshed every {AUDIT_REFRESH_MS / 1000} s.</p>
      {me === null ? (
        <Loading />
      ) : me.is_admin ? (
        <AuditSection />
      ) : (
        <Empty>
          The whole request log is for admins. Owners can read their twin's log with{" "}
          <code>GET /api/v1/gateway/audit?twin=SLUG</code> or <code>twinlink audit --twin SLUG</code>.
        </Empty>
      )}

      <h2>Services</h2>
      {twins.error ? (
        <ErrorMessage error={twins.error} onRetry={twins.reload} />
      ) : !twins.data ? (
        <Loading what="Loading services" />
      ) : twins.data.length === 0 ? (
        <Empty>No twin you may see has gateway services. A feature with an <code>apiAddress</code> becomes one.</Empty>
      ) : (
        twins.data.map((twin) => (
          <section key={twin.slug}>
            <h3>
              <Link to={`/twins/${encodeURIComponent(twin.slug)}`}>{twin.name}</Link>
            </h3>
            <table className="table">
              <thead>
                <tr>
                  <th>Service</th>
                  <th>Health</th>
                  <th>Base URL</th>
                  <th>Credentials</th>
                  <th className="num">Requests</th>
                </tr>
              </thead>
              <tbody>
                {twin.services.map((s) => (
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
                    </td>
                    <td className="num">{s.requests}</td>
                  </tr>
                ))}
              </tbody>
            </table>
          </section>
        ))
      )}
    </main>
  );
}
