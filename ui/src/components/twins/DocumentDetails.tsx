import type { TwinDocument } from "../../api/types";
import { AddressLink } from "./FeatureList";

const SHOWN_ELSEWHERE = new Set(["features", "relations", "name", "description", "interface"]);
/** A mapping of mappings with more keys than this reads better nested than as a table. */
const MAX_COLUMNS = 8;

/** A number as the document's YAML writes it, at its shortest: 2.1e11, not 210000000000. */
export function numberText(value: number): string {
  const plain = String(value);
  if (!Number.isInteger(value) || Math.abs(value) < 1e6 || plain.includes("e")) return plain;
  const digits = plain.replace("-", "");
  const significant = digits.replace(/0+$/, "");
  const mantissa = significant.length > 1 ? `${significant[0]}.${significant.slice(1)}` : significant;
  const scientific = `${value < 0 ? "-" : ""}${mantissa}e${digits.length - 1}`;
  return scientific.length < plain.length ? scientific : plain;
}

function isRecord(value: unknown): value is Record<string, unknown> {
  return typeof value === "object" && value !== null && !Array.isArray(value);
}

/** Entries of one shape (physical properties: {value, unit, source} by name) as a table. */
function EntryTable({ entries }: { entries: [string, Record<string, unknown>][] }) {
  const columns = [...new Set(entries.flatMap(([, row]) => Object.keys(row)))];
  return (
    <table className="table entry-table">
      <thead>
        <tr>
          <th />
          {columns.map((c) => (
            <th key={c}>{c}</th>
          ))}
        </tr>
      </thead>
      <tbody>
        {entries.map(([name, row]) => (
          <tr key={name}>
            <th scope="row">{name}</th>
            {columns.map((c) => (
              <td key={c}>{c in row ? <Value value={row[c]} /> : null}</td>
            ))}
          </tr>
        ))}
      </tbody>
    </table>
  );
}

function Value({ value }: { value: unknown }) {
  if (value === null || value === undefined) return <span className="muted">null</span>;
  if (typeof value === "string") return /^https?:\/\//i.test(value) ? <AddressLink href={value} /> : <>{value}</>;
  if (typeof value === "number") return <>{numberText(value)}</>;
  if (typeof value === "boolean") return <>{String(value)}</>;
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
  if (isRecord(value)) {
    const entries = Object.entries(value);
    if (entries.length > 1 && entries.every(([, v]) => isRecord(v))) {
      const rows = entries as [string, Record<string, unknown>][];
      if (new Set(rows.flatMap(([, row]) => Object.keys(row))).size <= MAX_COLUMNS) return <EntryTable entries={rows} />;
    }
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
