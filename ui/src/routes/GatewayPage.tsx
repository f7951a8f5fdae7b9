import { useEffect } from "react";
import { Link } from "react-router-dom";
import { listAudit, listServices } from "../api/gateway";
import { listTwins } from "../api/twins";
import type { Service } from "../api/types";
import { useAuth } from "../auth/AuthContext";
import { Empty, ErrorMessage, Loading } from "../components/common/Status";
import { AuditTable } from "../components/gateway/AuditTable";
import { ServicesTable } from "../components/gateway/ServicesTable";
import { useApi } from "../hooks/useApi";

export const AUDIT_REFRESH_MS = 5000;

/** Each twin's services; twins the user may not list services of are left out. */
interface TwinServices {
  slug: string;
  name: string;
  services: Service[];
}

async function servicesByTwin(signal: AbortSignal): Promise<TwinServices[]> {
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

function AuditSection({ twin }: { twin?: string }) {
  const audit = useApi((signal) => listAudit(100, signal, twin), [twin]);
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

/** For a user who is not an admin: the log of each twin they own (others answer 403). */
function OwnedAudit({ twins }: { twins: TwinServices[] | undefined }) {
  const owned = useApi(
    async (signal) => {
      const checks = await Promise.all(
        (twins ?? []).map((t) => listAudit(1, signal, t.slug).then(() => t, () => null)),
      );
      return checks.filter((t): t is TwinServices => t !== null);
    },
    [twins],
  );
  if (!twins || !owned.data) return <Loading />;
  if (owned.data.length === 0) {
    return <Empty>The request log is for admins and for the owners of a twin; you own no twin with services.</Empty>;
  }
  return (
    <>
      {owned.data.map((t) => (
        <section key={t.slug}>
          <h3>{t.name}</h3>
          <AuditSection twin={t.slug} />
        </section>
      ))}
    </>
  );
}

export function GatewayPage() {
  const { me } = useAuth();
  const twins = useApi(servicesByTwin, []);

  return (
    <main className="page">
      <h1>Gateway</h1>
      <section aria-labelledby="recent-requests">
        <h2 id="recent-requests">Recent requests</h2>
        <p className="muted">The newest 100 requests, refreshed every {AUDIT_REFRESH_MS / 1000} s.</p>
        {me === null ? (
          <Loading />
        ) : me.is_admin ? (
          <AuditSection />
        ) : (
          <OwnedAudit twins={twins.error ? [] : twins.data} />
        )}
      </section>

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
            <ServicesTable services={twin.services} />
          </section>
        ))
      )}
    </main>
  );
}
