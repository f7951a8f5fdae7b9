import { useEffect, useRef, useState } from "react";
import { serviceNameOf } from "../../api/gateway";
import type { Feature, Service } from "../../api/types";
import { Empty } from "../common/Status";
import { TryItPanel } from "../services/TryItPanel";
import { HealthBadge } from "../gateway/HealthBadge";
import { featureElementId, hashTarget } from "./featureAnchor";

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

/** The element id of each feature card: from its name, with a number added to a repeated one
 * so that ids stay unique (a search hit links to the first). */
export function featureElementIds(features: Feature[]): string[] {
  const used = new Set<string>();
  return features.map((feature) => {
    const base = featureElementId(feature.name);
    let id = base;
    for (let n = 2; used.has(id); n++) id = `${base}-${n}`;
    used.add(id);
    return id;
  });
}

interface FeatureCardProps {
  slug: string;
  feature: Feature;
  service?: Service;
  elementId: string;
  /** The location's hash points at this card: it is scrolled into view and highlighted. */
  targeted: boolean;
}

function FeatureCard({ slug, feature, service, elementId, targeted }: FeatureCardProps) {
  const [trying, setTrying] = useState(false);
  const ref = useRef<HTMLLIElement>(null);
  useEffect(() => {
    // jsdom has no scrollIntoView, hence the optional call.
    if (targeted) ref.current?.scrollIntoView?.({ block: "start" });
  }, [targeted]);
  return (
    <li ref={ref} id={elementId} className={targeted ? "card feature feature-target" : "card feature"}>
      <div className="feature-head">
        <h3>{feature.name}</h3>
        {service && (
          <>
            <span className="badge">service {service.name}</span>
            <HealthBadge service={service} />
          </>
        )}
        {!service && !feature.apiAddress && (
          <span className="badge" title="This feature has no API (no apiAddress): it is described here, and nothing is reachable through the gateway.">
            described only
          </span>
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

interface FeatureListProps {
  slug: string;
  features: Feature[];
  services: Service[];
  /** The location's hash; the feature card it names is scrolled to and highlighted. */
  hash?: string;
}

export function FeatureList({ slug, features, services, hash = "" }: FeatureListProps) {
  if (features.length === 0) return <Empty>This twin lists no features you may see.</Empty>;
  const ids = featureElementIds(features);
  const target = hashTarget(hash);
  return (
    <ul className="features">
      {features.map((feature, i) => (
        <FeatureCard
          key={`${feature.name}-${i}`}
          slug={slug}
          feature={feature}
          service={findService(feature, services)}
          elementId={ids[i] ?? featureElementId(feature.name)}
          targeted={target !== "" && target === ids[i]}
        />
      ))}
    </ul>
  );
}
