// One processor opened: its state and figures, actions for editors, events and logs.
import { useState } from "react";
import { getProcessor } from "../../api/processors";
import { ErrorMessage, Loading } from "../common/Status";
import { ProcessorActions } from "./ProcessorActions";
import { ProcessorConfig, ProcessorRunning, ProcessorStatus } from "./ProcessorFacts";
import { ProcessorEvents, ProcessorLogs } from "./ProcessorHistory";
import { ReconfigureForm } from "./ReconfigureForm";
import { usePolled } from "./usePolled";

interface Props {
  slug: string;
  name: string;
  editable: boolean;
  onChanged: () => void;
  onDeleted: (name: string) => void;
  onClose: () => void;
}

export function ProcessorDetail({ slug, name, editable, onChanged, onDeleted, onClose }: Props) {
  const processor = usePolled((signal) => getProcessor(slug, name, signal), [slug, name]);
  const [editing, setEditing] = useState(false);
  const p = processor.data;

  function changed() {
    processor.reload();
    onChanged();
  }

  return (
    <section className="card proc-detail" aria-label={`Processor ${name}`}>
      <div className="proc-toolbar">
        <h3>
          Processor <code>{name}</code>
        </h3>
        <span className="spacer" />
        <button type="button" onClick={onClose}>
          Close
        </button>
      </div>
      {processor.error && <ErrorMessage error={processor.error} onRetry={processor.reload} />}
      {!p && !processor.error && <Loading what="Loading the processor" />}
      {p && (
        <>
          {editable && <ProcessorActions slug={slug} processor={p} onChanged={changed} onDeleted={onDeleted} />}
          <div className="columns">
            <div>
              <h4>Status</h4>
              <ProcessorStatus processor={p} />
            </div>
            <div>
              <h4>Configuration</h4>
              <ProcessorConfig processor={p} />
            </div>
          </div>
          <h4>What it runs</h4>
          <ProcessorRunning processor={p} />
          {editable &&
            (editing ? (
              <ReconfigureForm slug={slug} processor={p} onSaved={changed} onClose={() => setEditing(false)} />
            ) : (
              <button type="button" onClick={() => setEditing(true)}>
                Edit parameters
              </button>
            ))}
        </>
      )}
      <h4>Events</h4>
      <ProcessorEvents slug={slug} name={name} />
      <h4>Logs</h4>
      <ProcessorLogs slug={slug} name={name} />
    </section>
  );
}
