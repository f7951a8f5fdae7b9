// Turning a command's declared parameters into form values and back into the JSON `args`.
import type { ParameterDecl } from "../../api/commands";

/** What a parameter's input holds: the text of a number or string input, or a checkbox. */
export type FieldValue = string | boolean;
export type FormValues = Record<string, FieldValue>;

/** The starting values: each parameter's declared default, else empty (bools: unchecked). */
export function initialValues(params: ParameterDecl[]): FormValues {
  const values: FormValues = {};
  for (const p of params) {
    if (p.type === "bool") values[p.name] = p.default === true;
    else values[p.name] = p.default === undefined || p.default === null ? "" : String(p.default);
  }
  return values;
}

export type ArgsOrError = { args: Record<string, unknown> } | { error: string };

/** The value of one parameter's input as JSON, `undefined` to leave it out, or an error. */
function parseValue(param: ParameterDecl, value: FieldValue | undefined): { value?: unknown; error?: string } {
  if (param.type === "bool") return { value: value === true };
  const text = typeof value === "string" ? value : "";
  if (param.type === "string") {
    // An empty optional string is left out, so the server fills in its default.
    if (text === "" && !param.required) return {};
    return { value: text };
  }
  if (text.trim() === "") return param.required ? { error: `${param.name} is required.` } : {};
  const number = Number(text);
  if (!Number.isFinite(number)) return { error: `${param.name}: "${text}" is not a number.` };
  if (param.type === "integer" && !Number.isInteger(number)) return { error: `${param.name}: ${text} is not a whole number.` };
  return { value: number };
}

/** The `args` to send. Types and required values are checked here; ranges are left to the
 * server, which answers 422 with a reason that names the limit. */
export function buildArgs(params: ParameterDecl[], values: FormValues): ArgsOrError {
  const args: Record<string, unknown> = {};
  for (const param of params) {
    const parsed = parseValue(param, values[param.name]);
    if (parsed.error) return { error: parsed.error };
    if (parsed.value !== undefined) args[param.name] = parsed.value;
  }
  return { args };
}

/** A short text of a range and unit, e.g. "1 to 100 Hz". */
export function describeRange(decl: { min?: number; max?: number; unit?: string }): string {
  const unit = decl.unit ? ` ${decl.unit}` : "";
  if (decl.min !== undefined && decl.max !== undefined) return `${decl.min} to ${decl.max}${unit}`;
  if (decl.min !== undefined) return `at least ${decl.min}${unit}`;
  if (decl.max !== undefined) return `at most ${decl.max}${unit}`;
  return decl.unit ?? "";
}

/** A JSON value in one line, for tables. */
export function compactJson(value: unknown): string {
  if (value === undefined) return "";
  const text = JSON.stringify(value);
  return text === undefined ? String(value) : text;
}
