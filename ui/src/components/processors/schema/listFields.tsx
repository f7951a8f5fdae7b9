// Lists: of texts or numbers typed comma separated, of choices as a row of checkboxes.
import { useEffect, useState } from "react";
import { namesSignal, useFormContext } from "./context";
import { FieldShell, hintText, type FieldProps } from "./fields";
import { parseNumber, unwrap } from "./schema";
import { useDraft } from "./useDraft";

const MAX_CHIPS = 16;

function splitList(text: string): string[] {
  return text
    .split(",")
    .map((part) => part.trim())
    .filter(Boolean);
}

/** A list of texts ("a, b") or numbers ("1, 2.5"); signal lists offer the stream's signals. */
export function ArrayTextField(props: FieldProps & { numbers: boolean }) {
  const { id, name, label, path, schema, value, onChange, required, nullable, numbers } = props;
  const { suggestions, markInvalid, root } = useFormContext();
  const integer = unwrap(schema.items ?? {}, root).schema.type === "integer";
  const [bad, setBad] = useState<string | null>(null);
  const list = Array.isArray(value) ? value : [];
  const [text, edit] = useDraft<unknown>(
    value,
    (v) => (Array.isArray(v) ? v.map(String).join(", ") : ""),
    (t) => {
      const parts = splitList(t);
      if (!parts.length) return { ok: true, value: undefined };
      if (!numbers) return { ok: true, value: parts };
      const values = parts.map((p) => parseNumber(p, integer));
      return values.some(Number.isNaN) ? { ok: false } : { ok: true, value: values };
    },
  );
  useEffect(() => () => markInvalid(path, false), [markInvalid, path]);

  function change(next: string) {
    const parsed = edit(next);
    setBad(parsed.ok ? null : "Type numbers separated by commas.");
    markInvalid(path, !parsed.ok);
    if (parsed.ok) onChange(parsed.value);
  }
  const offered = !numbers && namesSignal(name, schema) ? suggestions.filter((s) => !list.includes(s)).slice(0, MAX_CHIPS) : [];
  const hint = [hintText(schema, nullable), numbers ? "Numbers separated by commas." : "Separate several with commas."].join(" ");
  return (
    <FieldShell id={id} name={name} label={label} path={path} required={required} hint={hint}>
      <input
        id={id}
        value={text}
        placeholder={numbers ? "1, 2.5" : "first, second"}
        required={required}
        aria-invalid={bad ? true : undefined}
        aria-describedby={props.describedBy}
        onChange={(e) => change(e.target.value)}
      />
      {bad && <div className="sf-error">{bad}</div>}
      {offered.length > 0 && (
        <div className="sf-chips">
          <span className="sf-hint">Add a signal:</span>
          {offered.map((signal) => (
            <button key={signal} type="button" className="chip" onClick={() => onChange([...list, signal])}>
              + {signal}
            </button>
          ))}
        </div>
      )}
    </FieldShell>
  );
}

/** A list whose items come from an enum: one checkbox per choice. */
export function EnumArrayField({ id, name, label, path, schema, value, onChange, required, nullable }: FieldProps) {
  const { root, errors } = useFormContext();
  const options = (unwrap(schema.items ?? {}, root).schema.enum ?? []).map(String);
  const chosen = Array.isArray(value) ? value.map(String) : [];
  function toggle(option: string, on: boolean) {
    const next = options.filter((o) => (o === option ? on : chosen.includes(o)));
    onChange(next.length ? next : undefined);
  }
  const error = errors[path];
  return (
    <fieldset className={error ? "sf-group sf-field-bad" : "sf-group"} data-path={path}>
      <legend>
        {label} <code className="sf-key">{name}</code>
        {required && <span className="sf-required">required</span>}
      </legend>
      <div className="sf-checks">
        {options.map((option) => (
          <label key={option} className="sf-check">
            <input type="checkbox" checked={chosen.includes(option)} onChange={(e) => toggle(option, e.target.checked)} />
            {option}
          </label>
        ))}
      </div>
      <div className="sf-hint" id={`${id}-hint`}>
        {hintText(schema, nullable)}
      </div>
      {error && <div className="sf-error">{error}</div>}
    </fieldset>
  );
}
