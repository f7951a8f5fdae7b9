// Reading JSON schemas as pydantic emits them: $ref into $defs, allOf wrappers, optional
// fields written as anyOf [X, null], and the kind of input each schema is best edited with.
import type { JsonSchema } from "../../../api/processors";

export type FieldKind =
  | "string"
  | "number"
  | "integer"
  | "boolean"
  | "enum"
  | "stringArray"
  | "numberArray"
  | "enumArray"
  | "object"
  | "map"
  | "scalar"
  | "json";

const SCALAR_TYPES = new Set(["string", "number", "integer", "boolean"]);
const MAX_DEPTH = 8;

/** The schema a JSON pointer such as "#/$defs/CommandSpec" names in `root`, or undefined. */
export function lookupRef(ref: string, root: JsonSchema): JsonSchema | undefined {
  if (!ref.startsWith("#")) return undefined;
  let node: unknown = root;
  for (const raw of ref.slice(1).split("/").filter(Boolean)) {
    const key = raw.replace(/~1/g, "/").replace(/~0/g, "~");
    if (!node || typeof node !== "object") return undefined;
    node = (node as Record<string, unknown>)[key];
  }
  return node && typeof node === "object" ? (node as JsonSchema) : undefined;
}

/** Follow $ref and merge allOf, keeping the outer keywords (title, description, default) on top. */
export function resolve(schema: JsonSchema, root: JsonSchema, depth = 0): JsonSchema {
  if (depth > MAX_DEPTH) return schema;
  let result = schema;
  if (schema.$ref) {
    const target = lookupRef(schema.$ref, root);
    const { $ref: _ref, ...outer } = schema;
    result = target ? { ...resolve(target, root, depth + 1), ...outer } : outer;
  }
  if (result.allOf) {
    const { allOf, ...outer } = result;
    const merged = allOf.reduce<JsonSchema>((acc, part) => ({ ...acc, ...resolve(part, root, depth + 1) }), {});
    result = { ...merged, ...outer };
  }
  return result;
}

function isNull(schema: JsonSchema): boolean {
  return schema.type === "null" || (Array.isArray(schema.enum) && schema.enum.length === 1 && schema.enum[0] === null);
}

/** An optional field (`anyOf: [X, null]` or `type: [X, "null"]`) as X plus `nullable`. */
export function unwrap(schema: JsonSchema, root: JsonSchema): { schema: JsonSchema; nullable: boolean } {
  const base = resolve(schema, root);
  const choices = base.anyOf ?? base.oneOf;
  if (choices) {
    const rest = choices.filter((c) => !isNull(c));
    if (rest.length === 1 && rest.length < choices.length) {
      const { anyOf: _a, oneOf: _o, ...outer } = base;
      return { schema: { ...resolve(rest[0]!, root), ...outer }, nullable: true };
    }
  }
  if (Array.isArray(base.type) && base.type.includes("null")) {
    const types = base.type.filter((t) => t !== "null");
    return { schema: { ...base, type: types.length === 1 ? types[0] : types }, nullable: true };
  }
  return { schema: base, nullable: false };
}

/** The scalar types a union such as anyOf [number, integer, boolean, string] accepts, or null. */
export function scalarTypes(schema: JsonSchema, root: JsonSchema): string[] | null {
  const choices = schema.anyOf ?? schema.oneOf;
  const types = choices
    ? choices.map((c) => resolve(c, root).type)
    : Array.isArray(schema.type)
      ? schema.type
      : [schema.type];
  if (!types.length || !types.every((t) => typeof t === "string" && SCALAR_TYPES.has(t))) return null;
  return [...new Set(types as string[])];
}

function arrayKind(schema: JsonSchema, root: JsonSchema): FieldKind {
  const items = schema.items ? unwrap(schema.items, root).schema : undefined;
  if (!items) return "json";
  if (Array.isArray(items.enum) && items.enum.every((v) => typeof v === "string")) return "enumArray";
  if (items.type === "string") return "stringArray";
  if (items.type === "number" || items.type === "integer") return "numberArray";
  return "json";
}

function objectKind(schema: JsonSchema, root: JsonSchema): FieldKind {
  if (schema.properties) return "object";
  const extra = schema.additionalProperties;
  if (extra && typeof extra === "object") {
    const kind = fieldKind(unwrap(extra, root).schema, root);
    return ["string", "number", "integer", "boolean", "enum", "scalar"].includes(kind) ? "map" : "json";
  }
  return "json";
}

/** Which input edits a (resolved, unwrapped) schema; "json" is the raw JSON fallback. */
export function fieldKind(schema: JsonSchema, root: JsonSchema): FieldKind {
  if (Array.isArray(schema.enum) && schema.enum.length > 0) {
    return schema.enum.every((v) => typeof v === "string" || typeof v === "number") ? "enum" : "json";
  }
  switch (schema.type) {
    case "string":
      return "string";
    case "number":
      return "number";
    case "integer":
      return "integer";
    case "boolean":
      return "boolean";
    case "array":
      return arrayKind(schema, root);
    case "object":
      return objectKind(schema, root);
  }
  if (schema.properties) return "object";
  if (scalarTypes(schema, root)) return "scalar";
  return "json";
}

/** "cutoff_hz" -> "Cutoff hz", for properties without a title. */
export function humanize(key: string): string {
  const words = key.replace(/[_-]+/g, " ").trim();
  return words ? words[0]!.toUpperCase() + words.slice(1) : key;
}

/** Every property path of an object schema, dotted, below `prefix` (and `prefix` itself). */
export function schemaPaths(schema: JsonSchema, root: JsonSchema, prefix: string, depth = 0): string[] {
  const paths = [prefix];
  if (depth > MAX_DEPTH) return paths;
  const resolved = unwrap(schema, root).schema;
  for (const [key, prop] of Object.entries(resolved.properties ?? {})) {
    const path = prefix ? `${prefix}.${key}` : key;
    paths.push(...schemaPaths(prop, root, path, depth + 1));
  }
  return paths;
}

/** The number a text is, for number and integer fields; NaN when it is none. */
export function parseNumber(text: string, integer: boolean): number {
  const trimmed = text.trim();
  if (!trimmed) return Number.NaN;
  const value = Number(trimmed);
  if (!Number.isFinite(value)) return Number.NaN;
  return integer && !Number.isInteger(value) ? Number.NaN : value;
}

/** The value a text means for a union of scalar types: a number, true/false, or the text. */
export function parseScalar(text: string, types: string[]): unknown {
  const trimmed = text.trim();
  if (types.includes("boolean") && (trimmed === "true" || trimmed === "false")) return trimmed === "true";
  if (types.includes("number") || types.includes("integer")) {
    const value = parseNumber(trimmed, !types.includes("number"));
    if (!Number.isNaN(value)) return value;
  }
  return text;
}

/** The limits of a number field as a short text: "> 0", "1 … 10", "≤ 1". */
export function rangeText(schema: JsonSchema): string {
  const low =
    schema.exclusiveMinimum !== undefined ? `> ${schema.exclusiveMinimum}` : schema.minimum !== undefined ? `≥ ${schema.minimum}` : "";
  const high =
    schema.exclusiveMaximum !== undefined ? `< ${schema.exclusiveMaximum}` : schema.maximum !== undefined ? `≤ ${schema.maximum}` : "";
  return [low, high].filter(Boolean).join(", ");
}

/** A default value as shown to people. */
export function showValue(value: unknown): string {
  if (value === null) return "none";
  if (typeof value === "string") return value === "" ? '""' : value;
  return JSON.stringify(value);
}
