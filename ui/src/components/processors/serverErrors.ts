// Turning a 422 of the processor API into messages next to the fields they name.
//
// The server names a field in two ways: a request that does not fit the processor's shape has
// `errors: [{path: "body.rates.max_batch", message}]`, and a blueprint's parameters are checked
// later and reported in `detail` as "params: cutoff_hz: Input should be greater than 0" (several
// joined by "; "). Whatever names no field of the form is shown above it.
import { ApiError } from "../../api/client";

export interface FormErrors {
  /** Messages by the dotted path of the field they belong to ("params.cutoff_hz"). */
  fields: Record<string, string>;
  /** What names no known field, to show above the form; null when everything was placed. */
  general: string | null;
  /** The error as it came, for the summary line. */
  error: Error | null;
}

export const NO_ERRORS: FormErrors = { fields: {}, general: null, error: null };

const PATH = /^([A-Za-z_][\w-]*(?:\.[\w-]+)*): (.+)$/s;

function cleanMessage(message: string): string {
  return message.replace(/^Value error, /, "");
}

/** Split a detail such as "params: a: msg; b: msg" into (path, message) pairs. */
export function splitDetail(detail: string): { path: string | null; message: string }[] {
  let prefix = "";
  let rest = detail;
  if (rest.startsWith("params: ")) {
    prefix = "params.";
    rest = rest.slice("params: ".length);
  }
  return rest.split("; ").map((part) => {
    const match = PATH.exec(part);
    if (!match) return { path: null, message: part };
    return { path: prefix + match[1]!, message: cleanMessage(match[2]!) };
  });
}

/** The longest known path that `path` starts with ("params.signals.0" -> "params.signals"). */
export function matchPath(path: string, known: ReadonlySet<string>): string | null {
  const parts = path.split(".");
  for (let n = parts.length; n > 0; n--) {
    const candidate = parts.slice(0, n).join(".");
    if (known.has(candidate)) return candidate;
  }
  return null;
}

function pathErrors(problem: Record<string, unknown> | null): { path: string | null; message: string }[] | null {
  const errors = problem?.errors;
  if (!Array.isArray(errors) || errors.length === 0) return null;
  return errors.map((e: unknown) => {
    const item = (e ?? {}) as { path?: unknown; message?: unknown };
    const path = typeof item.path === "string" ? item.path.replace(/^body\.?/, "") : "";
    return { path: path || null, message: cleanMessage(String(item.message ?? "")) };
  });
}

/** Place the messages of an error at the fields of the form (`known` paths); the rest on top. */
export function formErrors(error: unknown, known: ReadonlySet<string>): FormErrors {
  const err = error instanceof Error ? error : new Error(String(error));
  if (!(err instanceof ApiError) || err.status !== 422) return { fields: {}, general: err.message, error: err };
  const parts = pathErrors(err.problem) ?? splitDetail(err.detail);
  const fields: Record<string, string> = {};
  const unplaced: string[] = [];
  for (const { path, message } of parts) {
    const at = path ? matchPath(path, known) : null;
    if (at) fields[at] = fields[at] ? `${fields[at]}; ${message}` : message;
    else unplaced.push(path ? `${path}: ${message}` : message);
  }
  return { fields, general: unplaced.length ? unplaced.join("; ") : null, error: err };
}
