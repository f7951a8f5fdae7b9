import { useState } from "react";
import { serviceNameOf } from "../../api/gateway";
import type { Feature, Service } from "../../api/types";
import { Empty } from "../common/Status";
import { TryItPanel } from "../services/TryItPanel";
import { HealthBadge } from "../gateway/HealthBadge";

/** A link when the address is a web address; other schemes (opc.tcp:, ...) show as text. */
export function AddressLink({ href }: { href: string }) {
  if (/^https?:\/\//i.test(href)) {
    return (
      <a href={href} target="_blank" rel="noreferrer noopener">
        {href}
      </a>
    );
  }
  return <span className="mono">{href}</span>;
}

export function findService(feature: Feature, services: Service[]): Service | undefined {
  return (
    services.find((s) => s.feature === feature.name) ?? services.find((s) => s.name === serviceNameOf(feature.name))
  );
}

function FeatureCard({ slug, feature, service }: { slug: string; feature: Feature; service?: Service }) {
  const [trying, setTrying] = useState(false);
  return (
    <li className="card feature">
      <div className="feature-head">
        <h3>{feature.name}</h3>
        {service && (
          <>
            <span className="badge">service {service.name}</span>
            <HealthBadge service={service} />
          </>
        )}
      </div>
      {feature.description && <p>{feature.description}</p>}
      <dl className="props">
        {feature.address && (
          <>
            <dt>Address</dt>
            <dd>
              <AddressLink href={feature.address} />
            </dd>
          </>
        )}
        {feature.apiAddress && (
          <>
            <dt>API</dt>
            <dd>
              <span className="mono">{feature.apiAddress}</span>
            </dd>
          </>
        )}
        {feature.documentation && (
          <>
            <dt>Documentation</dt>
            <dd>
              <AddressLink href={feature.documentation} />
            </dd>
          </>
        )}
        {feature.protocol && (
          <>
            <dt>Protocol</dt>
            <dd>{feature.protocol}</dd>
          </>
        )}
        {feature.requirement && (
          <>
            <dt>Requirement</dt>
            <dd>{feature.requirement}</dd>
          </>
        )}
      </dl>
      {feature.keywords && feature.keywords.length > 0 && (
        <div className="keywords">
          {feature.keywords.map((k) => (
            <span key={k} className="chip">
              {k}
            </span>
          ))}
        </div>
      )}
      {service && (
        <div>
          <button type="button" className="link-button" aria-expanded={trying} onClick={() => setTrying(!trying)}>
            {trying ? "Hide Try it" : "Try it"}
          </button>
          {trying && <TryItPanel slug={slug} service={service} />}
        </div>
      )}
    </li>
  );
}

export function FeatureList({ slug, features, services }: { slug: string; features: Feature[]; services: Service[] }) {
  if (features.length === 0) return <Empty>This twin lists no features you may see.</Empty>;
  return (
    <ul className="features">
      {features.map((feature, i) => (
        <FeatureCard key={`${feature.name}-${i}`} slug={slug} feature={feature} service={findService(feature, services)} />
      ))}
    </ul>
  );
}
