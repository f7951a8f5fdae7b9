// Commands, the command log and device properties of a twin, and the twin's declared
// `interface` read from its document (docs/api.md "Commands and properties").
import { apiFetch } from "./client";
import type { Schemas, TwinDocument } from "./types";

const enc = encodeURIComponent;

export type ValueType = "number" | "integer" | "bool" | "string";

/** A value the interface declares: a command parameter or a property. */
export interface ValueDecl {
  name: string;
  type: ValueType;
  unit?: string;
  min?: number;
  max?: number;
  description?: string;
}

export interface ParameterDecl extends ValueDecl {
  required: boolean;
  default?: unknown;
}

export interface CommandDecl {
  name: string;
  description?: string;
  parameters: ParameterDecl[];
}

export interface PropertyDecl extends ValueDecl {
  writable: boolean;
}

export interface TwinInterface {
  signals: ValueDecl[];
  commands: CommandDecl[];
  properties: PropertyDecl[];
  /** The device a command goes to when none is named (`interface.default_device`). */
  defaultDevice?: string;
}

export const COMMAND_STATES = ["pending", "delivered", "succeeded", "failed", "expired"] as const;
export type CommandState = (typeof COMMAND_STATES)[number];

export type CommandRecord = Schemas["CommandView"];

export type NewCommand = Schemas["NewCommand"];

export type TimedValue = Schemas["TimedProperty"];

export type DeviceProperties = Schemas["DeviceProperties"];

const VALUE_TYPES: readonly string[] = ["number", "integer", "bool", "string"];

function isRecord(value: unknown): value is Record<string, unknown> {
  return typeof value === "object" && value !== null && !Array.isArray(value);
}

function optionalNumber(value: unknown): number | undefined {
  return typeof value === "number" && Number.isFinite(value) ? value : undefined;
}

function optionalText(value: unknown): string | undefined {
  return typeof value === "string" ? value : undefined;
}

function named(items: unknown): Record<string, unknown>[] {
  return Array.isArray(items) ? items.filter((i): i is Record<string, unknown> => isRecord(i) && typeof i.name === "string") : [];
}

function valueDecl(raw: Record<string, unknown>): ValueDecl {
  // The server treats an unknown or missing type as "number"; so does the form.
  const type = typeof raw.type === "string" && VALUE_TYPES.includes(raw.type) ? (raw.type as ValueType) : "number";
  return {
    name: raw.name as string,
    type,
    unit: optionalText(raw.unit),
    min: optionalNumber(raw.min),
    max: optionalNumber(raw.max),
    description: optionalText(raw.description),
  };
}

/** The signals, commands and properties a twin's document declares (empty lists when it
 * declares none). */
export function readInterface(document: TwinDocument): TwinInterface {
  const raw = isRecord(document.interface) ? document.interface : {};
  const commands = named(raw.commands).map((c) => ({
    name: c.name as string,
    description: optionalText(c.description),
    parameters: named(c.parameters).map((p) => ({
      ...valueDecl(p),
      required: p.required === true,
      default: p.default ?? undefined,
    })),
  }));
  const properties = named(raw.properties).map((p) => ({ ...valueDecl(p), writable: p.writable === true }));
  const signals = named(raw.signals).map(valueDecl);
  return { signals, commands, properties, defaultDevice: optionalText(raw.default_device) };
}

/** The unit of each signal the interface declares with one. */
export function signalUnits(document: TwinDocument): Map<string, string> {
  const units = new Map<string, string>();
  for (const s of readInterface(document).signals) if (s.unit) units.set(s.name, s.unit);
  return units;
}

/** Whether a command is still under way (not succeeded, failed or expired). */
export function isOpen(record: CommandRecord): boolean {
  return record.state === "pending" || record.state === "delivered";
}

export function sendCommand(slug: string, command: NewCommand, signal?: AbortSignal): Promise<CommandRecord> {
  return apiFetch<CommandRecord>(`/api/v1/twins/${enc(slug)}/commands`, { method: "POST", json: command, signal });
}

export interface CommandFilter {
  state?: CommandState | "";
  name?: string;
  device?: string;
  limit?: number;
}

export async function listCommands(slug: string, filter: CommandFilter, signal?: AbortSignal): Promise<CommandRecord[]> {
  const answer = await apiFetch<{ commands: CommandRecord[] }>(`/api/v1/twins/${enc(slug)}/commands`, {
    query: { state: filter.state, name: filter.name, device: filter.device, limit: filter.limit },
    signal,
  });
  return answer.commands;
}

export function getCommand(slug: string, id: string, signal?: AbortSignal): Promise<CommandRecord> {
  return apiFetch<CommandRecord>(`/api/v1/twins/${enc(slug)}/commands/${enc(id)}`, { signal });
}

export function getProperties(slug: string, device: string, signal?: AbortSignal): Promise<DeviceProperties> {
  return apiFetch<DeviceProperties>(`/api/v1/twins/${enc(slug)}/devices/${enc(device)}/properties`, { signal });
}

/** Merge `changes` into the device's desired values; a null removes one. */
export function patchDesired(slug: string, device: string, changes: Record<string, unknown>): Promise<DeviceProperties> {
  return apiFetch<DeviceProperties>(`/api/v1/twins/${enc(slug)}/devices/${enc(device)}/properties/desired`, {
    method: "PATCH",
    json: changes,
  });
}
