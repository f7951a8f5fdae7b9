import { useState, type ReactNode } from "react";
import { useSearchParams } from "react-router-dom";
import { listProcessors, type Processor } from "../../api/processors";
import { Empty, ErrorMessage, Loading } from "../../components/common/Status";
import { CreateProcessor } from "../../components/processors/CreateProcessor";
import { FmuPanel } from "../../components/processors/FmuPanel";
import { ProcessorDetail } from "../../components/processors/ProcessorDetail";
import { ProcessorTable } from "../../components/processors/ProcessorTable";
import { usePolled } from "../../components/processors/usePolled";
import { canEdit, useTwin } from "./context";

/** The opened processor, kept in the address (?processor=name) so it can be linked to. */
function useSelectedProcessor(): [string | null, (name: string | null) => void] {
  const [search, setSearch] = useSearchParams();
  function select(name: string | null) {
    const next = new URLSearchParams(search);
    if (name) next.set("processor", name);
    else next.delete("processor");
    setSearch(next, { replace: true });
  }
  return [search.get("processor"), select];
}

function NoProcessors({ children }: { children: ReactNode }) {
  return (
    <Empty>
      <strong>No processors yet</strong>
      <p>
        A processor runs a blueprint (an FMU simulation, a filter, a moving window, a spectrum, an alarm) on one of this
        twin's streams and writes its results as another stream.
      </p>
      {children}
    </Empty>
  );
}

/** The twin's processors: the list (refreshed every few seconds), one opened in detail, the
 * create form and the uploaded FMUs. */
export function ProcessorsTab() {
  const { slug, twin } = useTwin();
  const editable = canEdit(twin);
  const processors = usePolled((signal) => listProcessors(slug, signal), [slug]);
  const [selected, select] = useSelectedProcessor();
  const [creating, setCreating] = useState(false);
  const [notice, setNotice] = useState<string | null>(null);
  const [fmusVersion, setFmusVersion] = useState(0);

  function created(processor: Processor) {
    setCreating(false);
    // A new worker is still being set up when the answer comes; the list shows when it runs.
    setNotice(processor.enabled ? `Created ${processor.name}; its worker is starting.` : `Created ${processor.name}, stopped.`);
    processors.reload();
    select(processor.name);
  }

  function deleted(name: string) {
    setNotice(`Deleted ${name}.`);
    select(null);
    processors.reload();
  }

  const list = processors.data;
  const newButton = editable && !creating && (
    <button type="button" onClick={() => { setCreating(true); setNotice(null); }}>
      New processor
    </button>
  );
  return (
    <section className="proc-tab" aria-label="Processors">
      <div className="proc-toolbar">
        <h2>Processors</h2>
        <span className="spacer" />
        {list && list.length > 0 && newButton}
      </div>
      {notice && (
        <div className="proc-result" role="status">
          {notice}
        </div>
      )}
      {creating && (
        <CreateProcessor slug={slug} existing={list ?? []} fmusVersion={fmusVersion} onCreated={created} onCancel={() => setCreating(false)} />
      )}
      {processors.error && <ErrorMessage error={processors.error} onRetry={processors.reload} />}
      {!list && !processors.error && <Loading what="Loading processors" />}
      {list && list.length === 0 && !creating && <NoProcessors>{newButton}</NoProcessors>}
      {list && list.length > 0 && <ProcessorTable processors={list} selected={selected} onSelect={select} />}
      {selected && (
        <ProcessorDetail
          key={selected}
          slug={slug}
          name={selected}
          editable={editable}
          onChanged={processors.reload}
          onDeleted={deleted}
          onClose={() => select(null)}
        />
      )}
      <FmuPanel slug={slug} editable={editable} version={fmusVersion} onUploaded={() => setFmusVersion((v) => v + 1)} />
    </section>
  );
}
