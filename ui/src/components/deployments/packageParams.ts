// A twin package's parameters, read from its twin.yaml: the JSON schema the deployment form is
// generated from, the defaults it starts with, and the checks made before anything is sent
// (the server checks again; these only spare a round trip and point at the field).
import { load } from "js-yaml";
import type { JsonSchema } from "../../api/processors";
import { rangeText, unwrap } from "../processors/schema/schema";

export interface PackageInfo {
  description: string | null;
  /** The parameters' schema (an object schema), or null when the package takes none. */
  parameters: JsonSchema | null;
}

function isObject(value: unknown): value is Record<string, unknown> {
  return value !== null && typeof value === "object" && !Array.isArray(value);
}

/** A YAMLException as one line: its reason and where ("line 2, column 1"). */
function yamlProblem(err: unknown): string {
  const e = (err ?? {}) as { reason?: unknown; mark?: { line?: unknown; column?: unknown }; message?: unknown };
  if (typeof e.reason === "string" && typeof e.mark?.line === "number" && typeof e.mark.column === "number") {
    return `${e.reason} (line ${e.mark.line + 1}, column ${e.mark.column + 1})`;
  }
  return err instanceof Error ? err.message : String(err);
}

/** Read twin.yaml's text; an Error a person can act on when it is not a package description. */
export function parseTwinYaml(text: string): PackageInfo {
  let doc: unknown;
  try {
    doc = load(text, { filename: "twin.yaml" });
  } catch (err) {
    throw new Error(`twin.yaml is not valid YAML: ${yamlProblem(err)}`);
  }
  if (doc === undefined || doc === null) return { description: null, parameters: null };
  if (!isObject(doc)) throw new Error("twin.yaml must be a mapping (description, parameters, document, ...)");
  const description = typeof doc.description === "string" ? doc.description : null;
  const raw = doc.parameters;
  if (raw === undefined || raw === null) return { description, parameters: null };
  if (!isObject(raw)) throw new Error("twin.yaml: `parameters` must be a JSON schema of an object");
  const parameters = raw as JsonSchema;
  if (parameters.type !== undefined && parameters.type !== "object") {
    throw new Error(`twin.yaml: \`parameters\` must describe an object, not a ${String(parameters.type)}`);
  }
  return { description, parameters };
}

/** The starting values of the form: every top-level property's default. */
export function parameterDefaults(schema: JsonSchema | null): Record<string, unknown> {
  const values: Record<string, unknown> = {};
  for (const [key, prop] of Object.entries(schema?.properties ?? {})) {
    const resolved = unwrap(prop, schema!).schema;
    if (resolved.default !== undefined) values[key] = structuredClone(resolved.default);
  }
  return values;
}

function checkNumber(schema: JsonSchema, value: number): string | null {
  if (schema.type === "integer" && !Number.isInteger(value)) return "must be a whole number";
  const low = schema.minimum !== undefined && value < schema.minimum;
  const lowEx = schema.exclusiveMinimum !== undefined && value <= schema.exclusiveMinimum;
  const high = schema.maximum !== undefined && value > schema.maximum;
  const highEx = schema.exclusiveMaximum !== undefined && value >= schema.exclusiveMaximum;
  return low || lowEx || high || highEx ? `must be ${rangeText(schema)}` : null;
}

function checkValue(schema: JsonSchema, value: unknown): string | null {
  if (Array.isArray(schema.enum) && schema.enum.length > 0) {
    return schema.enum.some((option) => option === value) ? null : `must be one of ${schema.enum.map(String).join(", ")}`;
  }
  switch (schema.type) {
    case "number":
    case "integer":
      return typeof value === "number" ? checkNumber(schema, value) : "must be a number";
    case "boolean":
      return typeof value === "boolean" ? null : "must be true or false";
    case "string":
      if (typeof value !== "string") return "must be a text";
      if (schema.minLength !== undefined && value.length < schema.minLength) return `must be at least ${schema.minLength} characters`;
      if (schema.maxLength !== undefined && value.length > schema.maxLength) return `must be at most ${schema.maxLength} characters`;
      return null;
  }
  return null;
}

/** Messages by dotted path ("parameters.zeta") for the values that break the schema. */
export function checkParameters(schema: JsonSchema | null, values: Record<string, unknown>, prefix = "parameters"): Record<string, string> {
  const problems: Record<string, string> = {};
  if (!schema) return problems;
  const required = new Set(schema.required ?? []);
  for (const [key, prop] of Object.entries(schema.properties ?? {})) {
    const path = `${prefix}.${key}`;
    const value = values[key];
    if (value === undefined || value === null) {
      if (required.has(key) && unwrap(prop, schema).schema.default === undefined) problems[path] = "is required";
      continue;
    }
    const problem = checkValue(unwrap(prop, schema).schema, value);
    if (problem) problems[path] = problem;
  }
  return problems;
}
