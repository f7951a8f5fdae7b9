import { useState, type FormEvent } from "react";
import { ErrorMessage } from "../common/Status";
import { CommandOutcome } from "./CommandOutcome";
import { useSendCommand, type SendTarget } from "./useSendCommand";

interface Props {
  slug: string;
  target: SendTarget;
  disabled: boolean;
  onSent: () => void;
}

function parseArgs(text: string): Record<string, unknown> {
  if (!text.trim()) return {};
  const parsed: unknown = JSON.parse(text);
  if (typeof parsed !== "object" || parsed === null || Array.isArray(parsed)) {
    throw new Error("The arguments must be a JSON object, e.g. {\"value\": 50}.");
  }
  return parsed as Record<string, unknown>;
}

/** Any command name with JSON arguments, for a twin whose interface declares no commands. */
export function FreeCommandForm({ slug, target, disabled, onSent }: Props) {
  const [name, setName] = useState("");
  const [argsText, setArgsText] = useState("");
  const { record, setRecord, error, setError, sending, send } = useSendCommand(slug, target, onSent);

  function submit(event: FormEvent) {
    event.preventDefault();
    if (!name.trim()) {
      setError(new Error("Give the command a name."));
      return;
    }
    let args: Record<string, unknown>;
    try {
      args = parseArgs(argsText);
    } catch (err) {
      setError(new Error(err instanceof SyntaxError ? `The arguments are not valid JSON: ${err.message}` : (err as Error).message));
      return;
    }
    void send(name.trim(), args);
  }

  return (
    <section className="card command-card">
      <h3>Any command</h3>
      <p className="muted command-description">
        The twin&apos;s interface declares no commands, so any name and any JSON arguments are sent to the device as they are.
      </p>
      <form className="command-form" onSubmit={submit} aria-label="Free command">
        <label className="param">
          <span className="param-label">Command name</span>
          <input className="mono" value={name} disabled={disabled} onChange={(e) => setName(e.target.value)} placeholder="set_sample_rate" />
        </label>
        <label className="param param-wide">
          <span className="param-label">Arguments (JSON object)</span>
          <textarea className="mono" rows={3} value={argsText} disabled={disabled} onChange={(e) => setArgsText(e.target.value)} placeholder='{"value": 50}' />
        </label>
        <button type="submit" disabled={disabled || sending}>
          {sending ? "Sending…" : "Send"}
        </button>
      </form>
      {error && <ErrorMessage error={error} />}
      {record && <CommandOutcome slug={slug} record={record} onUpdate={setRecord} />}
    </section>
  );
}
