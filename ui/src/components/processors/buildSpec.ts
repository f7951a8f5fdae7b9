// What the create form holds, and the body of POST .../processors it makes (docs/processors.md).
import type { FmuVariable, InputMap, ProcessorSpec, Rates } from "../../api/processors";
import { parseNumber } from "./schema/schema";

/** One row of the input mapping: blueprint input <- source signal * scale + offset. */
export interface InputRow {
  input: string;
  signal: string;
  scale?: number;
  offset?: number;
}

/** Where one FMU input comes from; an empty signal leaves the input unfed. */
export interface FmuFeed {
  signal: string;
  scale?: number;
  offset?: number;
}

/** The FMU mapping view's state for the `fmu` blueprint. */
export interface FmuChoice {
  fmu: string;
  /** The FMU's variables once loaded (GET .../fmus/{name}); null before. */
  variables: FmuVariable[] | null;
  feeds: Record<string, FmuFeed>;
  outputs: string[];
  /** Values typed for parameters and start values, by variable name; empty: the FMU's start. */
  parameters: Record<string, string>;
}

export interface Limits {
  rates: Partial<Rates>;
  memory_limit_mb?: number;
  batch_timeout_s?: number;
}

export interface CreateDraft {
  name: string;
  blueprint: string;
  source: string;
  /** Empty: the processor's name. */
  output: string;
  enabled: boolean;
  inputs: InputRow[];
  params: Record<string, unknown>;
  limits: Limits;
  fmu: FmuChoice | null;
}

const FLOAT_TYPES = new Set(["Real", "Float64", "Float32"]);
const INT_TYPES = new Set(["Integer", "Enumeration", "Int8", "UInt8", "Int16", "UInt16", "Int32", "UInt32", "Int64", "UInt64"]);

const scalar = (v: FmuVariable) => !v.shape || v.shape.length === 0;

/** The FMU inputs a processor can feed (real scalars, as the blueprint requires). */
export function fmuInputs(variables: FmuVariable[]): FmuVariable[] {
  return variables.filter((v) => v.causality === "input" && (v.type === "Real" || v.type === "Float64") && scalar(v));
}

/** The FMU outputs that can be written to a stream (numbers and booleans). */
export function fmuOutputs(variables: FmuVariable[]): FmuVariable[] {
  return variables.filter(
    (v) => v.causality === "output" && (FLOAT_TYPES.has(v.type) || INT_TYPES.has(v.type) || v.type === "Boolean") && scalar(v),
  );
}

/** Parameters, which can be set before initialisation by name. */
export function fmuParameters(variables: FmuVariable[]): FmuVariable[] {
  return variables.filter((v) => v.causality === "parameter" && scalar(v));
}

/** A fresh mapping for a loaded FMU: each input fed from the signal of its own name when the
 * source has one, every output chosen, no parameter changed. */
export function initialFmuChoice(fmu: string, variables: FmuVariable[], signals: string[]): FmuChoice {
  const feeds: Record<string, FmuFeed> = {};
  for (const v of fmuInputs(variables)) feeds[v.name] = { signal: signals.includes(v.name) ? v.name : "" };
  return { fmu, variables, feeds, outputs: fmuOutputs(variables).map((v) => v.name), parameters: {} };
}

function parameterValue(variable: FmuVariable | undefined, text: string): number | boolean | string | null {
  const trimmed = text.trim();
  const type = variable?.type ?? "Real";
  if (type === "Boolean") {
    if (["true", "1"].includes(trimmed.toLowerCase())) return true;
    if (["false", "0"].includes(trimmed.toLowerCase())) return false;
    return null;
  }
  if (FLOAT_TYPES.has(type) || INT_TYPES.has(type)) {
    const value = parseNumber(trimmed, INT_TYPES.has(type));
    return Number.isNaN(value) ? null : value;
  }
  return text;
}

export interface FmuParts {
  inputs: Record<string, InputMap>;
  params: Record<string, unknown>;
  /** Messages by path ("params.parameters") for what cannot be sent as it is. */
  problems: Record<string, string>;
}

/** The processor's `inputs` and the FMU blueprint's `fmu`, `inputs`, `outputs`, `parameters`. */
export function buildFmuParts(choice: FmuChoice): FmuParts {
  const variables = choice.variables ?? [];
  const feedable = fmuInputs(variables).map((v) => v.name);
  const fed = feedable.filter((name) => choice.feeds[name]?.signal);
  const inputs: Record<string, InputMap> = {};
  for (const name of fed) {
    const feed = choice.feeds[name]!;
    inputs[name] = { signal: feed.signal, scale: feed.scale ?? 1, offset: feed.offset ?? 0 };
  }
  const params: Record<string, unknown> = { fmu: choice.fmu };
  // Left out, the blueprint feeds every input; an unfed one must then be left out by name.
  if (fed.length < feedable.length) params.inputs = fed;
  const order = variables.map((v) => v.name);
  params.outputs = [...choice.outputs].sort((a, b) => order.indexOf(a) - order.indexOf(b));
  const problems: Record<string, string> = {};
  const parameters: Record<string, unknown> = {};
  const bad: string[] = [];
  for (const [name, text] of Object.entries(choice.parameters)) {
    if (!text.trim()) continue;
    const value = parameterValue(variables.find((v) => v.name === name), text);
    if (value === null) bad.push(name);
    else parameters[name] = value;
  }
  if (Object.keys(parameters).length) params.parameters = parameters;
  if (bad.length) problems["params.parameters"] = `Not a value of the variable's type: ${bad.join(", ")}.`;
  if (!choice.outputs.length) problems["params.outputs"] = "Choose at least one output.";
  if (!choice.fmu) problems["params.fmu"] = "Choose an FMU.";
  return { inputs, params, problems };
}

function definedOnly<T extends object>(value: T): Partial<T> {
  return Object.fromEntries(Object.entries(value).filter(([, v]) => v !== undefined && v !== "")) as Partial<T>;
}

/** The input mapping rows that name both an input and a signal. */
export function rowsToInputs(rows: InputRow[]): Record<string, InputMap> {
  const inputs: Record<string, InputMap> = {};
  for (const row of rows) {
    if (row.input.trim() && row.signal.trim()) {
      inputs[row.input.trim()] = { signal: row.signal.trim(), scale: row.scale ?? 1, offset: row.offset ?? 0 };
    }
  }
  return inputs;
}

/** The body of POST .../processors, and what must be fixed before it can be sent. */
export function buildSpec(draft: CreateDraft): { spec: ProcessorSpec; problems: Record<string, string> } {
  const fmu = draft.blueprint === "fmu" && draft.fmu ? buildFmuParts(draft.fmu) : null;
  const inputs = fmu ? fmu.inputs : rowsToInputs(draft.inputs);
  const spec: ProcessorSpec = {
    name: draft.name.trim(),
    blueprint: draft.blueprint,
    source: draft.source,
    enabled: draft.enabled,
    params: fmu ? { ...draft.params, ...fmu.params } : draft.params,
  };
  if (draft.output.trim()) spec.output = draft.output.trim();
  if (Object.keys(inputs).length) spec.inputs = inputs;
  const rates = definedOnly(draft.limits.rates);
  if (Object.keys(rates).length) spec.rates = rates;
  if (draft.limits.memory_limit_mb !== undefined) spec.memory_limit_mb = draft.limits.memory_limit_mb;
  if (draft.limits.batch_timeout_s !== undefined) spec.batch_timeout_s = draft.limits.batch_timeout_s;
  const problems = { ...(fmu?.problems ?? {}) };
  if (draft.blueprint === "fmu" && !draft.fmu) problems["params.fmu"] = "Choose an FMU.";
  if (!spec.name) problems.name = "Give the processor a name.";
  return { spec, problems };
}

/** A name not yet taken: the blueprint's own, or with -2, -3... */
export function freeName(base: string, taken: string[]): string {
  const clean = base.toLowerCase().replace(/[^a-z0-9_-]+/g, "-").replace(/^[^a-z]+/, "") || "processor";
  if (!taken.includes(clean)) return clean;
  let n = 2;
  while (taken.includes(`${clean}-${n}`)) n++;
  return `${clean}-${n}`;
}
