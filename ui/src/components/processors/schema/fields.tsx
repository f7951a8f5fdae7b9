// The inputs of single values: text, number, checkbox, choice, and a union of scalars.
import type { ReactNode } from "react";
import type { JsonSchema } from "../../../api/processors";
import { namesSignal, useFormContext } from "./context";
import { useDraft } from "./useDraft";
import { parseNumber, parseScalar, rangeText, scalarTypes, showValue } from "./schema";

export interface FieldProps {
  id: string;
  /** The property's key in its object. */
  name: string;
  label: string;
  /** Dotted path of the value, for server errors ("params.cutoff_hz"). */
  path: string;
  /** Resolved and unwrapped (an optional field's non-null choice). */
  schema: JsonSchema;
  value: unknown;
  onChange: (value: unknown) => void;
  required: boolean;
  nullable: boolean;
  /** Ids of the hint and error texts, for aria-describedby. */
  describedBy?: string;
}

/** The hint under a field: its description, default and limits. */
export function hintText(schema: JsonSchema, nullable: boolean): string {
  const parts: string[] = [];
  if (schema.description) parts.push(schema.description);
  if (schema.default !== undefined && schema.default !== null) parts.push(`Default: ${showValue(schema.default)}.`);
  else if (nullable) parts.push("Optional: leave empty for none.");
  const range = rangeText(schema);
  if (range) parts.push(`Allowed: ${range}.`);
  return parts.join(" ");
}

interface ShellProps {
  id: string;
  name: string;
  label: string;
  path: string;
  required: boolean;
  hint: string;
  children: ReactNode;
  /** A checkbox carries its own label: the shell then shows none. */
  ownLabel?: boolean;
}

/** Label, key, "required", the input, its hint and the server's message for it. */
export function FieldShell({ id, name, label, path, required, hint, children, ownLabel }: ShellProps) {
  const { errors } = useFormContext();
  const error = errors[path];
  return (
    <div className={error ? "sf-field sf-field-bad" : "sf-field"} data-path={path}>
      {!ownLabel && (
        <div className="sf-label">
          <label htmlFor={id}>{label}</label>
          <code className="sf-key">{name}</code>
          {required && <span className="sf-required">required</span>}
        </div>
      )}
      {children}
      {hint && (
        <div className="sf-hint" id={`${id}-hint`}>
          {hint}
        </div>
      )}
      {error && (
        <div className="sf-error" id={`${id}-error`}>
          {error}
        </div>
      )}
    </div>
  );
}

export function StringInput({ id, name, schema, value, onChange, required, describedBy }: FieldProps) {
  const { suggestions, suggestionsId } = useFormContext();
  const offer = suggestions.length > 0 && namesSignal(name, schema);
  return (
    <input
      id={id}
      value={typeof value === "string" ? value : value === undefined || value === null ? "" : String(value)}
      placeholder={typeof schema.default === "string" && schema.default ? schema.default : undefined}
      list={offer ? suggestionsId : undefined}
      required={required}
      aria-describedby={describedBy}
      onChange={(e) => onChange(e.target.value === "" && !required ? undefined : e.target.value)}
    />
  );
}

export function NumberInput({ id, schema, value, onChange, required, describedBy }: FieldProps) {
  const integer = schema.type === "integer";
  return (
    <input
      id={id}
      type="number"
      step={integer ? 1 : "any"}
      min={schema.minimum}
      max={schema.maximum}
      value={typeof value === "number" ? value : ""}
      placeholder={typeof schema.default === "number" ? String(schema.default) : undefined}
      required={required}
      aria-describedby={describedBy}
      onChange={(e) => {
        const parsed = parseNumber(e.target.value, integer);
        onChange(Number.isNaN(parsed) ? undefined : parsed);
      }}
    />
  );
}

export function BooleanInput({ id, label, schema, value, onChange, describedBy }: FieldProps) {
  const checked = typeof value === "boolean" ? value : schema.default === true;
  return (
    <label className="sf-check" htmlFor={id}>
      <input id={id} type="checkbox" checked={checked} aria-describedby={describedBy} onChange={(e) => onChange(e.target.checked)} />
      {label}
    </label>
  );
}

export function EnumInput({ id, schema, value, onChange, required, nullable, describedBy }: FieldProps) {
  const options = schema.enum ?? [];
  const index = options.findIndex((o) => o === value);
  const unset =
    schema.default !== undefined && schema.default !== null
      ? `default (${showValue(schema.default)})`
      : nullable || !required
        ? "none"
        : "Choose…";
  return (
    <select
      id={id}
      value={index >= 0 ? String(index) : ""}
      required={required}
      aria-describedby={describedBy}
      onChange={(e) => onChange(e.target.value === "" ? undefined : options[Number(e.target.value)])}
    >
      <option value="">{unset}</option>
      {options.map((option, i) => (
        <option key={String(option)} value={String(i)}>
          {String(option)}
        </option>
      ))}
    </select>
  );
}

/** A value that may be a number, a boolean or a text: typed as text, read as what it looks like. */
export function ScalarInput({ id, schema, value, onChange, required, describedBy }: FieldProps) {
  const { root } = useFormContext();
  const types = scalarTypes(schema, root) ?? ["string"];
  const [text, edit] = useDraft<unknown>(
    value,
    (v) => (v === undefined || v === null ? "" : String(v)),
    (t) => ({ ok: true, value: t === "" ? undefined : parseScalar(t, types) }),
  );
  return (
    <input
      id={id}
      value={text}
      placeholder={types.join(" or ")}
      required={required}
      aria-describedby={describedBy}
      onChange={(e) => onChange(edit(e.target.value).value)}
    />
  );
}

/** The input for a single value of this kind (inside a map's rows or a field's shell). */
export function ScalarField(props: FieldProps & { kind: string }) {
  switch (props.kind) {
    case "number":
    case "integer":
      return <NumberInput {...props} />;
    case "boolean":
      return <BooleanInput {...props} />;
    case "enum":
      return <EnumInput {...props} />;
    case "scalar":
      return <ScalarInput {...props} />;
    default:
      return <StringInput {...props} />;
  }
}
