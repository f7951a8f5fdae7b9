import { useState } from "react";
import { deleteProcessor, processorAction, type Processor, type ProcessorAction } from "../../api/processors";
import { ErrorMessage } from "../common/Status";

interface Props {
  slug: string;
  processor: Processor;
  /** After a change: load the processor and the list again. */
  onChanged: () => void;
  onDeleted: (name: string) => void;
}

const DONE: Record<ProcessorAction, string> = {
  start: "Start requested",
  stop: "Stopped",
  restart: "Restart requested",
};

/** Start, Stop, Restart and Delete (editors), each with what came of it. */
export function ProcessorActions({ slug, processor, onChanged, onDeleted }: Props) {
  const [busy, setBusy] = useState<string | null>(null);
  const [result, setResult] = useState<string | null>(null);
  const [error, setError] = useState<Error>();
  const name = processor.name;
  const hosted = processor.state !== "stopped";

  async function run(label: string, work: () => Promise<string>) {
    setBusy(label);
    setResult(null);
    setError(undefined);
    try {
      setResult(await work());
    } catch (err) {
      setError(err instanceof Error ? err : new Error(String(err)));
    } finally {
      setBusy(null);
    }
  }

  function act(action: ProcessorAction) {
    void run(action, async () => {
      const answer = await processorAction(slug, name, action);
      onChanged();
      return `${DONE[action]}: ${name} is ${answer.state}.`;
    });
  }

  function remove() {
    const question = `Delete the processor ${name}? Its worker is stopped and its settings and events are removed; the data it wrote stays.`;
    if (!window.confirm(question)) return;
    void run("delete", async () => {
      await deleteProcessor(slug, name);
      onDeleted(name);
      return `Deleted ${name}.`;
    });
  }

  return (
    <div className="proc-actions">
      <div className="proc-buttons" role="group" aria-label={`Actions on ${name}`}>
        <button type="button" disabled={busy !== null || processor.enabled} onClick={() => act("start")}>
          Start
        </button>
        <button type="button" disabled={busy !== null || !processor.enabled} onClick={() => act("stop")}>
          Stop
        </button>
        <button type="button" disabled={busy !== null || !hosted} onClick={() => act("restart")}>
          Restart
        </button>
        <button type="button" className="proc-danger" disabled={busy !== null} onClick={remove}>
          Delete
        </button>
        {busy && <span className="muted">Working…</span>}
      </div>
      {result && (
        <div className="proc-result" role="status">
          {result}
        </div>
      )}
      {error && <ErrorMessage error={error} />}
    </div>
  );
}
