import type { PropertyDecl } from "../../api/commands";
import { formatTime } from "../common/Status";
import { compactJson, describeRange, type FieldValue } from "./commandForm";
import { editorValue, isWritable, type PropertyRowData } from "./propertyValues";

interface Props {
  rows: PropertyRowData[];
  /** Whether the interface declares properties (then only writable ones may be set). */
  declared: boolean;
  editable: boolean;
  busy: boolean;
  drafts: Record<string, FieldValue>;
  onDraft: (name: string, value: FieldValue) => void;
  onRemove: (name: string) => void;
}

function DesiredInput({ row, value, disabled, onDraft }: { row: PropertyRowData; value: FieldValue; disabled: boolean; onDraft: (v: FieldValue) => void }) {
  const decl: PropertyDecl | undefined = row.decl;
  const label = `Desired ${row.name}`;
  if (decl?.type === "bool") {
    return <input type="checkbox" aria-label={label} checked={value === true} disabled={disabled} onChange={(e) => onDraft(e.target.checked)} />;
  }
  const numeric = decl?.type === "number" || decl?.type === "integer";
  return (
    <input
      aria-label={label}
      className="mono desired-input"
      type={numeric ? "number" : "text"}
      step={decl?.type === "integer" ? 1 : numeric ? "any" : undefined}
      min={decl?.min}
      max={decl?.max}
      value={typeof value === "string" ? value : ""}
      placeholder={decl ? "" : "50, true or \"text\""}
      disabled={disabled}
      onChange={(e) => onDraft(e.target.value)}
    />
  );
}

function Row({ row, props }: { row: PropertyRowData; props: Props }) {
  const writable = props.editable && isWritable(row, props.declared);
  const draft = props.drafts[row.name];
  const hint = row.decl ? [row.decl.type, describeRange(row.decl), row.decl.writable ? "" : "read-only"].filter(Boolean).join(" · ") : "";
  return (
    <tr className={draft !== undefined ? "row-changed" : undefined}>
      <td title={row.decl?.description}>
        <span className="mono">{row.name}</span>
        {hint && <div className="param-hint">{hint}</div>}
      </td>
      <td>
        {row.reported ? (
          <>
            <span className="mono">{compactJson(row.reported.value)}</span>
            <div className="param-hint">{formatTime(row.reported.time)}</div>
          </>
        ) : (
          <span className="muted">not reported</span>
        )}
      </td>
      <td>
        {writable ? (
          <DesiredInput row={row} value={draft ?? editorValue(row)} disabled={props.busy} onDraft={(v) => props.onDraft(row.name, v)} />
        ) : row.desired ? (
          <span className="mono">{compactJson(row.desired.value)}</span>
        ) : (
          <span className="muted">—</span>
        )}
      </td>
      <td>
        {row.pending && (
          <span className="badge badge-pending" title="The desired value differs from the reported one: the device has not applied it yet.">
            ≠ not applied
          </span>
        )}
      </td>
      {props.editable && (
        <td>
          {writable && row.desired && (
            <button type="button" className="link-button" disabled={props.busy} onClick={() => props.onRemove(row.name)}>
              Remove
            </button>
          )}
        </td>
      )}
    </tr>
  );
}

/** Property name | reported (value, time) | desired | delta marker; desired values editable. */
export function PropertyTable(props: Props) {
  return (
    <table className="table properties-table">
      <thead>
        <tr>
          <th>Property</th>
          <th>Reported</th>
          <th>Desired</th>
          <th>Delta</th>
          {props.editable && <th aria-label="Actions" />}
        </tr>
      </thead>
      <tbody>
        {props.rows.map((row) => (
          <Row key={row.name} row={row} props={props} />
        ))}
      </tbody>
    </table>
  );
}
