// The fields of the create form that every blueprint shares.
import type { ReactNode } from "react";
import type { Blueprint, Rates } from "../../api/processors";
import type { CreateDraft, Limits } from "./buildSpec";
import { dedent } from "./format";

interface PlainFieldProps {
  id: string;
  label: string;
  hint?: string;
  error?: string;
  path: string;
  required?: boolean;
  children: ReactNode;
}

/** A labelled input with its hint and the server's message for it. */
export function PlainField({ id, label, hint, error, path, required, children }: PlainFieldProps) {
  return (
    <div className={error ? "sf-field sf-field-bad" : "sf-field"} data-path={path}>
      <div className="sf-label">
        <label htmlFor={id}>{label}</label>
        {required && <span className="sf-required">required</span>}
      </div>
      {children}
      {hint && <div className="sf-hint">{hint}</div>}
      {error && <div className="sf-error">{error}</div>}
    </div>
  );
}

interface PickerProps {
  blueprints: Blueprint[];
  value: string;
  onChange: (name: string) => void;
  error?: string;
}

export function BlueprintPicker({ blueprints, value, onChange, error }: PickerProps) {
  const chosen = blueprints.find((b) => b.name === value);
  return (
    <PlainField id="proc-blueprint" label="Blueprint" path="blueprint" error={error} required>
      <select id="proc-blueprint" value={value} required onChange={(e) => onChange(e.target.value)}>
        <option value="">Choose what the processor runs…</option>
        {blueprints.map((b) => (
          <option key={b.name} value={b.name} disabled={Boolean(b.error)}>
            {b.name}: {b.error ? `cannot be loaded (${b.error})` : (b.title ?? b.name)}
          </option>
        ))}
      </select>
      {chosen && (
        <div className="proc-doc" aria-label={`About ${chosen.name}`}>
          {dedent(chosen.description ?? chosen.title ?? "")}
          {chosen.keeps_state && <div className="muted">Takes new parameters while running, keeping its state.</div>}
        </div>
      )}
    </PlainField>
  );
}

interface BasicsProps {
  draft: CreateDraft;
  onChange: (change: Partial<CreateDraft>) => void;
  streams: string[];
  errors: Record<string, string>;
}

export function BasicsFields({ draft, onChange, streams, errors }: BasicsProps) {
  return (
    <div className="proc-basics">
      <PlainField id="proc-name" label="Name" path="name" error={errors.name} required hint="Lowercase letters, digits, _ and -, starting with a letter; unique in the twin.">
        <input id="proc-name" className="mono" value={draft.name} required onChange={(e) => onChange({ name: e.target.value })} />
      </PlainField>
      <PlainField id="proc-source" label="Source stream" path="source" error={errors.source} hint="The stream it reads.">
        <select id="proc-source" value={draft.source} onChange={(e) => onChange({ source: e.target.value })}>
          {streams.map((s) => (
            <option key={s} value={s}>
              {s}
            </option>
          ))}
        </select>
      </PlainField>
      <PlainField id="proc-output" label="Output stream" path="output" error={errors.output} hint="The stream it writes. Empty: the processor's name.">
        <input id="proc-output" className="mono" value={draft.output} placeholder={draft.name} onChange={(e) => onChange({ output: e.target.value })} />
      </PlainField>
      <div className="sf-field" data-path="enabled">
        <label className="sf-check">
          <input type="checkbox" checked={draft.enabled} onChange={(e) => onChange({ enabled: e.target.checked })} />
          Enabled
        </label>
        <div className="sf-hint">Runs at once and after a server restart; off: created stopped.</div>
        {errors.enabled && <div className="sf-error">{errors.enabled}</div>}
      </div>
    </div>
  );
}

const RATE_FIELDS: [keyof Rates, string, string][] = [
  ["min_input_spacing_s", "Min input spacing (s)", "Input samples closer than this to the last one used are skipped. Default 0."],
  ["min_step_spacing_s", "Min step spacing (s)", "Shortest time between steps, for blueprints that step. Default 0."],
  ["min_output_spacing_s", "Min output spacing (s)", "Output samples closer than this to the last one sent are dropped. Default 0."],
  ["max_batch", "Max batch", "Most samples handed to the blueprint at once. Default 10000."],
];

function num(text: string): number | undefined {
  const value = Number(text);
  return text.trim() === "" || !Number.isFinite(value) ? undefined : value;
}

export function LimitsFields({ limits, onChange, errors }: { limits: Limits; onChange: (l: Limits) => void; errors: Record<string, string> }) {
  const open = Object.keys(errors).some((k) => k.startsWith("rates") || k === "memory_limit_mb" || k === "batch_timeout_s");
  return (
    <details className="proc-details" open={open}>
      <summary>Rates and limits</summary>
      <div className="proc-grid">
        {RATE_FIELDS.map(([key, label, hint]) => (
          <PlainField key={key} id={`proc-${key}`} label={label} hint={hint} path={`rates.${key}`} error={errors[`rates.${key}`] ?? errors.rates}>
            <input id={`proc-${key}`} type="number" step="any" min={0} value={limits.rates[key] ?? ""} onChange={(e) => onChange({ ...limits, rates: { ...limits.rates, [key]: num(e.target.value) } })} />
          </PlainField>
        ))}
        <PlainField id="proc-memory" label="Memory limit (MB)" hint="The worker is restarted above this resident memory. Default 1024." path="memory_limit_mb" error={errors.memory_limit_mb}>
          <input id="proc-memory" type="number" min={16} placeholder="1024" value={limits.memory_limit_mb ?? ""} onChange={(e) => onChange({ ...limits, memory_limit_mb: num(e.target.value) })} />
        </PlainField>
        <PlainField id="proc-timeout" label="Batch timeout (s)" hint="A worker stuck this long on one batch is restarted. Default 30." path="batch_timeout_s" error={errors.batch_timeout_s}>
          <input id="proc-timeout" type="number" step="any" placeholder="30" value={limits.batch_timeout_s ?? ""} onChange={(e) => onChange({ ...limits, batch_timeout_s: num(e.target.value) })} />
        </PlainField>
      </div>
    </details>
  );
}
