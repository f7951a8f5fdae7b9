import type { TwinDocument } from "../../api/types";
import { AddressLink } from "./FeatureList";

const SHOWN_ELSEWHERE = new Set(["features", "relations", "name", "description", "interface"]);

function Value({ value }: { value: unknown }) {
  if (value === null || value === undefined) return <span className="muted">—</span>;
  if (typeof value === "string") return /^https?:\/\//i.test(value) ? <AddressLink href={value} /> : <>{value}</>;
  if (typeof value === "number" || typeof value === "boolean") return <>{String(value)}</>;
  if (Array.isArray(value) && value.every((v) => typeof v === "string")) return <>{value.join(", ")}</>;
  if (Array.isArray(value)) {
    // Lists of entries (relations' extra keys, custom lists) keep their nesting.
    return (
      <ol className="nested-list">
        {value.map((item, i) => (
          <li key={i}>
            <Value value={item} />
          </li>
        ))}
      </ol>
    );
  }
  if (typeof value === "object" && !Array.isArray(value)) {
    return (
      <dl className="props nested">
        {Object.entries(value as Record<string, unknown>).map(([k, v]) => (
          <div key={k} className="prop-row">
            <dt>{k}</dt>
            <dd>
              <Value value={v} />
            </dd>
          </div>
        ))}
      </dl>
    );
  }
  return <code>{String(value)}</code>;
}

/** The document's fields other than features, relations and the interface (shown as tables),
 * and the whole document as JSON. */
export function DocumentDetails({ document }: { document: TwinDocument }) {
  const entries = Object.entries(document).filter(([k]) => !SHOWN_ELSEWHERE.has(k));
  return (
    <div>
      <dl className="props">
        {entries.map(([key, value]) => (
          <div key={key} className="prop-row">
            <dt>{key}</dt>
            <dd>
              <Value value={value} />
            </dd>
          </div>
        ))}
      </dl>
      <details>
        <summary>The document as JSON</summary>
        <pre className="answer-body">{JSON.stringify(document, null, 2)}</pre>
      </details>
    </div>
  );
}
