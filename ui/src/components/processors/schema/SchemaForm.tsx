// A form generated from a JSON schema (a blueprint's parameters), editing a JSON object.
import { useCallback, useId, useMemo, useRef } from "react";
import type { JsonSchema } from "../../../api/processors";
import { FormContext, useFormContext, type SchemaFormContext } from "./context";
import { FieldShell, hintText, ScalarField, type FieldProps } from "./fields";
import { JsonField } from "./JsonField";
import { ArrayTextField, EnumArrayField } from "./listFields";
import { MapField } from "./MapField";
import { fieldKind, humanize, unwrap } from "./schema";
import "../processors.css";

type JsonObject = Record<string, unknown>;

export interface SchemaFormProps {
  schema: JsonSchema;
  value: JsonObject;
  onChange: (value: JsonObject) => void;
  /** The path of the value in the request, for server errors ("params"). */
  path?: string;
  /** Server messages by dotted path ("params.cutoff_hz"). */
  errors?: Record<string, string>;
  /** Top-level properties edited elsewhere (the FMU view edits `fmu`, `outputs`...). */
  omit?: string[];
  /** Signal names offered in fields that name signals. */
  suggestions?: string[];
  /** Told whether any field holds text that cannot be used (JSON that does not parse). */
  onValidity?: (valid: boolean) => void;
}

function asObject(value: unknown): JsonObject {
  return value && typeof value === "object" && !Array.isArray(value) ? (value as JsonObject) : {};
}

export function SchemaForm({ schema, value, onChange, path = "", errors = {}, omit = [], suggestions = [], onValidity }: SchemaFormProps) {
  const suggestionsId = useId();
  const invalid = useRef(new Set<string>());
  const markInvalid = useCallback(
    (at: string, bad: boolean) => {
      const before = invalid.current.size;
      if (bad) invalid.current.add(at);
      else invalid.current.delete(at);
      if (before !== invalid.current.size) onValidity?.(invalid.current.size === 0);
    },
    [onValidity],
  );
  const context = useMemo<SchemaFormContext>(
    () => ({ root: schema, errors, suggestions, suggestionsId, markInvalid }),
    [schema, errors, suggestions, suggestionsId, markInvalid],
  );
  const root = unwrap(schema, schema).schema;
  return (
    <FormContext.Provider value={context}>
      <div className="schema-form">
        {errors[path] && <div className="sf-error">{errors[path]}</div>}
        {fieldKind(root, schema) === "object" ? (
          <ObjectFields schema={root} value={value} onChange={onChange} path={path} omit={omit} />
        ) : (
          <p className="muted">This blueprint takes no parameters a form can show.</p>
        )}
        <datalist id={suggestionsId}>
          {suggestions.map((s) => (
            <option key={s} value={s} />
          ))}
        </datalist>
      </div>
    </FormContext.Provider>
  );
}

interface ObjectFieldsProps {
  schema: JsonSchema;
  value: JsonObject;
  onChange: (value: JsonObject) => void;
  path: string;
  omit?: string[];
}

/** One field per property of an object schema, in the schema's order. */
export function ObjectFields({ schema, value, onChange, path, omit = [] }: ObjectFieldsProps) {
  const required = new Set(schema.required ?? []);
  function set(key: string, next: unknown) {
    const copy = { ...value };
    if (next === undefined) delete copy[key];
    else copy[key] = next;
    onChange(copy);
  }
  const keys = Object.keys(schema.properties ?? {}).filter((k) => !omit.includes(k));
  if (!keys.length) return <p className="muted">No parameters.</p>;
  return (
    <>
      {keys.map((key) => (
        <SchemaField
          key={key}
          name={key}
          schema={schema.properties![key]!}
          value={value[key]}
          required={required.has(key)}
          path={path ? `${path}.${key}` : key}
          onChange={(next) => set(key, next)}
        />
      ))}
    </>
  );
}

interface SchemaFieldProps {
  name: string;
  schema: JsonSchema;
  value: unknown;
  required: boolean;
  path: string;
  onChange: (value: unknown) => void;
}

/** The right input for one property, by the kind of its schema. */
export function SchemaField({ name, schema: raw, value, required, path, onChange }: SchemaFieldProps) {
  const { root, errors } = useFormContext();
  const id = useId();
  const { schema, nullable } = unwrap(raw, root);
  const kind = fieldKind(schema, root);
  const label = raw.title ?? (schema.title && kind !== "object" ? schema.title : humanize(name));
  const describedBy = [`${id}-hint`, errors[path] ? `${id}-error` : ""].filter(Boolean).join(" ");
  const props: FieldProps = { id, name, label, path, schema, value, onChange, required, nullable, describedBy };
  switch (kind) {
    case "object":
      return <ObjectField {...props} />;
    case "map":
      return <MapField {...props} />;
    case "json":
      return <JsonField {...props} />;
    case "stringArray":
    case "numberArray":
      return <ArrayTextField {...props} numbers={kind === "numberArray"} />;
    case "enumArray":
      return <EnumArrayField {...props} />;
  }
  return (
    <FieldShell id={id} name={name} label={label} path={path} required={required} hint={hintText(schema, nullable)} ownLabel={kind === "boolean"}>
      <ScalarField {...props} kind={kind} />
    </FieldShell>
  );
}

/** A nested object in a fieldset; an optional one is switched on with a checkbox first. */
function ObjectField({ id, name, label, path, schema, value, onChange, required, nullable }: FieldProps) {
  const { errors } = useFormContext();
  const present = value !== undefined && value !== null;
  const optional = nullable || !required;
  return (
    <fieldset className="sf-group" data-path={path}>
      <legend>
        {label} <code className="sf-key">{name}</code>
        {required && <span className="sf-required">required</span>}
      </legend>
      {schema.description && (
        <div className="sf-hint" id={`${id}-hint`}>
          {schema.description}
        </div>
      )}
      {errors[path] && <div className="sf-error">{errors[path]}</div>}
      {optional && (
        <label className="sf-check">
          <input type="checkbox" checked={present} onChange={(e) => onChange(e.target.checked ? {} : undefined)} />
          Set {label}
        </label>
      )}
      {(present || !optional) && <ObjectFields schema={schema} value={asObject(value)} onChange={onChange} path={path} />}
    </fieldset>
  );
}
