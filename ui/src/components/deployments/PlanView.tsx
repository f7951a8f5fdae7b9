// What a deployment (or a change to one) will do, as `terraform plan` shows it: the resources
// created, updated (with each changed value), deleted and kept. Tokens are never in a plan.
import type { Plan, PlanChange, PlanItem } from "../../api/deployments";

const SECTIONS = [
  { key: "create", title: "Create", mark: "+", className: "plan-create" },
  { key: "update", title: "Update", mark: "~", className: "plan-update" },
  { key: "delete", title: "Delete", mark: "−", className: "plan-delete" },
  { key: "keep", title: "Keep", mark: "=", className: "plan-keep" },
] as const;

/** A value of a change as a short text: JSON, "none" for a missing one. */
export function showPlanValue(value: unknown): string {
  if (value === undefined || value === null) return "none";
  return typeof value === "string" ? value : JSON.stringify(value);
}

/** "3 to create, 1 to update, 0 to delete" */
export function planSummary(plan: Plan): string {
  return `${plan.create.length} to create, ${plan.update.length} to update, ${plan.delete.length} to delete`;
}

function Changes({ changes }: { changes: PlanChange[] }) {
  return (
    <ul className="plan-changes">
      {changes.map((change) => (
        <li key={change.path}>
          <code>{change.path}</code>: <span className="plan-from">{showPlanValue(change.from)}</span> →{" "}
          <span className="plan-to">{showPlanValue(change.to)}</span>
        </li>
      ))}
    </ul>
  );
}

function Item({ item, mark }: { item: PlanItem; mark: string }) {
  return (
    <li>
      <span className="plan-mark" aria-hidden="true">
        {mark}
      </span>{" "}
      <span className="badge">{item.type}</span> <strong>{item.name}</strong>
      {item.changes && item.changes.length > 0 && <Changes changes={item.changes} />}
      {item.spec !== undefined && item.type !== "twin" && (
        <details>
          <summary>Specification</summary>
          <pre className="answer-body">{JSON.stringify(item.spec, null, 2)}</pre>
        </details>
      )}
    </li>
  );
}

export function PlanView({ plan }: { plan: Plan }) {
  const empty = (["create", "update", "delete"] as const).every((key) => (plan[key] ?? []).length === 0);
  return (
    <section className="card plan" aria-label="Plan">
      <p>
        <strong>Plan:</strong> {planSummary(plan)}.
      </p>
      {empty && <p className="muted">Nothing to do.</p>}
      {SECTIONS.map(({ key, title, mark, className }) => {
        const items = plan[key] ?? [];
        if (!items.length) return null;
        return (
          <div key={key} className={className}>
            <h4>
              {title} ({items.length})
            </h4>
            <ul className="plain-list" aria-label={title}>
              {items.map((item) => (
                <Item key={`${item.type}:${item.name}`} item={item} mark={mark} />
              ))}
            </ul>
          </div>
        );
      })}
    </section>
  );
}
