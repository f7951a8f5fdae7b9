// The rows of a device's property table and the conversion of edited desired values to JSON.
import type { DeviceProperties, PropertyDecl } from "../../api/commands";
import type { FieldValue } from "./commandForm";

export interface PropertyRowData {
  name: string;
  decl?: PropertyDecl;
  reported?: { value: unknown; time: string };
  desired?: { value: unknown; time: string };
  /** The device has not applied the desired value yet. */
  pending: boolean;
}

/** Declared properties first (in their order), then any other reported or desired name. */
export function propertyRows(decls: PropertyDecl[], props: DeviceProperties): PropertyRowData[] {
  const names = decls.map((d) => d.name);
  const others = new Set([...Object.keys(props.reported), ...Object.keys(props.desired)]);
  for (const name of names) others.delete(name);
  return [...names, ...[...others].sort()].map((name) => ({
    name,
    decl: decls.find((d) => d.name === name),
    reported: props.reported[name],
    desired: props.desired[name],
    pending: Object.prototype.hasOwnProperty.call(props.delta, name),
  }));
}

/** Whether people may set the property: any name when the interface declares no
 * properties, else only the writable ones. */
export function isWritable(row: { decl?: PropertyDecl }, declared: boolean): boolean {
  return declared ? row.decl?.writable === true : true;
}

/** What an editor input starts from: the desired value as text (bools as a checkbox). */
export function editorValue(row: PropertyRowData): FieldValue {
  const value = row.desired?.value;
  if (row.decl?.type === "bool") return value === true;
  if (value === undefined || value === null) return "";
  if (!row.decl && typeof value === "string") return JSON.stringify(value);
  return String(value);
}

/** A loosely typed value of an undeclared property: JSON numbers, true/false and "quoted"
 * text are taken as such; anything else is sent as a string. */
export function parseLoose(text: string): unknown {
  try {
    const parsed: unknown = JSON.parse(text);
    if (typeof parsed === "number" || typeof parsed === "boolean" || typeof parsed === "string") return parsed;
  } catch {
    // not JSON: plain text
  }
  return text;
}

/** The JSON value of an edited desired value, or an error that says what is wrong. */
export function toDesired(name: string, decl: PropertyDecl | undefined, value: FieldValue): { value: unknown } | { error: string } {
  if (typeof value === "boolean") return { value };
  if (!decl) return { value: parseLoose(value) };
  if (decl.type === "string") return { value };
  if (decl.type === "bool") return { value: value === "true" };
  if (value.trim() === "") return { error: `${name}: give a number, or use Remove to take the desired value away.` };
  const number = Number(value);
  if (!Number.isFinite(number)) return { error: `${name}: "${value}" is not a number.` };
  if (decl.type === "integer" && !Number.isInteger(number)) return { error: `${name}: ${value} is not a whole number.` };
  return { value: number };
}
