import { useLocation } from "react-router-dom";
import { listServices } from "../../api/gateway";
import { getRelations } from "../../api/twins";
import { ErrorMessage } from "../../components/common/Status";
import { ConnectorsSection } from "../../components/connectors/ConnectorsSection";
import { DevicesSection } from "../../components/devices/DevicesSection";
import { RolesSection } from "../../components/roles/RolesSection";
import { DocumentDetails } from "../../components/twins/DocumentDetails";
import { ExportButtons } from "../../components/twins/ExportButtons";
import { InterfaceTables } from "../../components/twins/InterfaceTables";
import { FeatureList, findService } from "../../components/twins/FeatureList";
import { RelationLinks } from "../../components/twins/Relations";
import { HealthBadge } from "../../components/gateway/HealthBadge";
import { useApi } from "../../hooks/useApi";
import { canEdit, useTwin } from "./context";

export function OverviewTab() {
  const { slug, twin } = useTwin();
  // A search hit links to a feature as /twins/{slug}#feature-{anchor}: that card is scrolled
  // to and highlighted.
  const { hash } = useLocation();
  // The rest needs the viewer role; a user who sees only the public part gets 403 or 404 here,
  // which the sections show as their own message.
  const services = useApi((signal) => listServices(slug, signal), [slug]);
  const parents = useApi((signal) => getRelations(slug, "up", signal), [slug]);
  const children = useApi((signal) => getRelations(slug, "down", signal), [slug]);

  const { document } = twin;
  const features = document.features ?? [];
  const serviceList = services.data ?? [];
  const otherServices = serviceList.filter((s) => !features.some((f) => findService(f, [s])));

  return (
    <>
      <p className="muted">
        <span className="mono">{twin.id}</span> · your role: {twin.role ?? "none"} · parts:{" "}
        {twin.levels.join(", ")} · <a href={twin.url}>canonical page</a>
      </p>
      <ExportButtons slug={slug} />
      {document.description && <p className="lead">{document.description}</p>}

      <h2>Features</h2>
      {services.error && <p className="muted">Services: {services.error.message}</p>}
      <FeatureList slug={slug} features={features} services={serviceList} hash={hash} />
      {otherServices.length > 0 && (
        <>
          <h3>Other gateway services</h3>
          <FeatureList
            slug={slug}
            features={otherServices.map((s) => ({ name: s.name, description: s.description ?? undefined }))}
            services={otherServices}
            hash={hash}
          />
        </>
      )}

      <h2>Relations</h2>
      {parents.error || children.error ? (
        <ErrorMessage error={(parents.error ?? children.error) as Error} />
      ) : (
        <div className="columns">
          <RelationLinks title="Parents" root={parents.data} />
          <RelationLinks title="Children" root={children.data} />
        </div>
      )}

      <DevicesSection slug={slug} canEdit={canEdit(twin)} />
      <ConnectorsSection slug={slug} canManage={twin.role === "admin"} />
      <RolesSection slug={slug} role={twin.role} />

      {serviceList.length > 0 && (
        <>
          <h2>Service health</h2>
          <ul className="inline-list">
            {serviceList.map((s) => (
              <li key={s.name}>
                {s.name} <HealthBadge service={s} />
              </li>
            ))}
          </ul>
        </>
      )}

      {document.interface !== undefined && (
        <>
          <h2>Interface</h2>
          <InterfaceTables document={document} />
        </>
      )}

      <h2>Document</h2>
      <DocumentDetails document={document} />
    </>
  );
}
