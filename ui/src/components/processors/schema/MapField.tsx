// An object of free keys (additionalProperties), such as an FMU's `parameters` or an
// expression's `outputs`: one row of name and value per entry.
import { useEffect, useRef, useState } from "react";
import { useFormContext } from "./context";
import { FieldShell, hintText, ScalarField, type FieldProps } from "./fields";
import { fieldKind, unwrap } from "./schema";

type Row = [string, unknown];

function rowsOf(value: unknown): Row[] {
  return value && typeof value === "object" && !Array.isArray(value) ? Object.entries(value) : [];
}

function objectOf(rows: Row[]): Record<string, unknown> | undefined {
  const kept = rows.filter(([key, v]) => key.trim() && v !== undefined);
  return kept.length ? Object.fromEntries(kept.map(([k, v]) => [k.trim(), v])) : undefined;
}

export function MapField({ id, name, label, path, schema, value, onChange, required, nullable }: FieldProps) {
  const { root } = useFormContext();
  const valueSchema = unwrap(typeof schema.additionalProperties === "object" ? schema.additionalProperties : {}, root);
  const kind = fieldKind(valueSchema.schema, root);
  const [rows, setRows] = useState<Row[]>(() => rowsOf(value));
  const produced = useRef<unknown>(objectOf(rowsOf(value)));

  useEffect(() => {
    // A value set from outside (a reset) replaces the rows; our own edits do not.
    if (JSON.stringify(objectOf(rowsOf(value))) !== JSON.stringify(produced.current)) {
      produced.current = objectOf(rowsOf(value));
      setRows(rowsOf(value));
    }
  }, [value]);

  function update(next: Row[]) {
    setRows(next);
    produced.current = objectOf(next);
    onChange(produced.current);
  }
  const hint = hintText(schema, nullable);
  return (
    <FieldShell id={id} name={name} label={label} path={path} required={required} hint={hint}>
      <div className="sf-map" id={id} role="group" aria-label={label}>
        {rows.map(([key, v], i) => (
          <div className="sf-map-row" key={i}>
            <input
              aria-label={`${label}: name ${i + 1}`}
              className="mono"
              value={key}
              placeholder="name"
              onChange={(e) => update(rows.map((r, j) => (j === i ? [e.target.value, r[1]] : r)))}
            />
            <span aria-hidden="true">=</span>
            <label className="sf-sr" htmlFor={`${id}-v${i}`}>{`${label}: value ${i + 1}`}</label>
            <ScalarField
              id={`${id}-v${i}`}
              name={key}
              label={key || `value ${i + 1}`}
              path={`${path}.${key}`}
              schema={valueSchema.schema}
              value={v}
              required={false}
              nullable={valueSchema.nullable}
              kind={kind}
              onChange={(next) => update(rows.map((r, j) => (j === i ? [r[0], next] : r)))}
            />
            <button type="button" className="link-button" aria-label={`Remove ${label} entry ${i + 1}`} onClick={() => update(rows.filter((_, j) => j !== i))}>
              Remove
            </button>
          </div>
        ))}
        <button type="button" onClick={() => setRows([...rows, ["", undefined]])}>
          Add entry
        </button>
      </div>
    </FieldShell>
  );
}
