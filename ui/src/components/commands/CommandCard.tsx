import { useState, type FormEvent } from "react";
import type { CommandDecl } from "../../api/commands";
import { ErrorMessage } from "../common/Status";
import { CommandOutcome } from "./CommandOutcome";
import { ParamInput } from "./ParamInput";
import { buildArgs, initialValues, type FieldValue, type FormValues } from "./commandForm";
import { useSendCommand, type SendTarget } from "./useSendCommand";

interface Props {
  slug: string;
  command: CommandDecl;
  target: SendTarget;
  disabled: boolean;
  onSent: () => void;
}

/** One declared command: its description, a form made from its parameters, and its result. */
export function CommandCard({ slug, command, target, disabled, onSent }: Props) {
  const [values, setValues] = useState<FormValues>(() => initialValues(command.parameters));
  const { record, setRecord, error, setError, sending, send } = useSendCommand(slug, target, onSent);

  function submit(event: FormEvent) {
    event.preventDefault();
    const built = buildArgs(command.parameters, values);
    if ("error" in built) {
      setError(new Error(built.error));
      return;
    }
    void send(command.name, built.args);
  }

  const setValue = (name: string) => (value: FieldValue) => setValues((v) => ({ ...v, [name]: value }));
  return (
    <section className="card command-card">
      <h3 className="mono">{command.name}</h3>
      {command.description && <p className="muted command-description">{command.description}</p>}
      {/* noValidate: the server checks ranges and answers with a reason that names the limit */}
      <form className="command-form" onSubmit={submit} noValidate aria-label={`Command ${command.name}`}>
        {command.parameters.map((p) => (
          <ParamInput key={p.name} param={p} value={values[p.name]} disabled={disabled} onChange={setValue(p.name)} />
        ))}
        {command.parameters.length === 0 && <span className="muted">No parameters.</span>}
        <button type="submit" disabled={disabled || sending}>
          {sending ? "Sending…" : "Send"}
        </button>
      </form>
      {error && <ErrorMessage error={error} />}
      {record && <CommandOutcome slug={slug} record={record} onUpdate={setRecord} />}
    </section>
  );
}
