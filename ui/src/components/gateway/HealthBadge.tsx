import type { Service } from "../../api/types";

export function HealthBadge({ service }: { service: Pick<Service, "health" | "blocked" | "health_path"> }) {
  if (service.blocked) return <span className="badge badge-bad" title={service.blocked}>blocked</span>;
  const health = service.health;
  if (!health) {
    return (
      <span className="badge" title={service.health_path ? "not checked yet" : "no health path set"}>
        {service.health_path ? "unchecked" : "no health check"}
      </span>
    );
  }
  const title = `${health.path ?? ""}: ${health.http_status ?? "no answer"} in ${health.ms} ms${health.error ? ` (${health.error})` : ""}`;
  return (
    <span className={health.status === "up" ? "badge badge-ok" : "badge badge-bad"} title={title}>
      {health.status}
    </span>
  );
}
