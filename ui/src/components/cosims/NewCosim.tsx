// Create a co-simulation from a file: a Maestro multi-model (.json), twinlink's YAML form, or
// a folder as a zip or tar (an SSP archive, or one document beside its FMUs). The File is the
// request's body, so the browser streams it from disk; its type follows its name.
import { useId, useState, type FormEvent } from "react";
import { contentTypeOf, createCosim, nameFromFile, startCosim, type Cosim, type CosimMode } from "../../api/cosims";
import { listAllTwins } from "../../api/twins";
import { useApi } from "../../hooks/useApi";
import { ErrorMessage } from "../common/Status";
import { PlainField } from "../processors/CreateFields";

export const ACCEPT = ".json,.yaml,.yml,.zip,.ssp,.tar,.tgz,.tar.gz";
/** The twins offered to write the results to: the first this many the user may see. */
const TWINS_LISTED = 200;

interface Props {
  /** Made; `startError` when it was made but would not start (an algebraic loop, no end time
   * in batch): its page says why. */
  onCreated: (cosim: Cosim, startError?: string) => void;
  onCancel: () => void;
}

/** What is wrong with the form, by field; nothing when it may be sent. */
export function checkForm(values: { file: File | null; name: string; factor: string; mode: CosimMode }): Record<string, string> {
  const found: Record<string, string> = {};
  if (!values.file) found.file = "choose a Maestro .json, a .yaml, or a zip, .ssp or tar archive";
  else if (!contentTypeOf(values.file.name)) found.file = `${values.file.name} is none of .json, .yaml, .yml, .zip, .ssp, .tar, .tgz, .tar.gz`;
  if (!values.name.trim()) found.name = "give it a name";
  const factor = Number(values.factor);
  if (values.mode === "realtime" && !(Number.isFinite(factor) && factor > 0)) found.factor = "a number above 0: 1 is the wall clock, 2 twice as fast";
  return found;
}

export function NewCosim({ onCreated, onCancel }: Props) {
  const id = useId();
  const twins = useApi((signal) => listAllTwins(TWINS_LISTED, signal), []);
  const [file, setFile] = useState<File | null>(null);
  const [name, setName] = useState("");
  const [twin, setTwin] = useState("");
  const [prefix, setPrefix] = useState("");
  const [stream, setStream] = useState("");
  const [mode, setMode] = useState<CosimMode>("batch");
  const [factor, setFactor] = useState("1");
  const [start, setStart] = useState(true);
  const [problems, setProblems] = useState<Record<string, string>>({});
  const [error, setError] = useState<Error | null>(null);
  const [busy, setBusy] = useState(false);

  function chooseFile(next: File | null) {
    setFile(next);
    if (next && !name) setName(nameFromFile(next.name));
  }

  async function submit(event: FormEvent) {
    event.preventDefault();
    const found = checkForm({ file, name, factor, mode });
    setProblems(found);
    if (Object.keys(found).length || !file) return;
    setBusy(true);
    setError(null);
    try {
      const cosim = await createCosim({ file, name: name.trim(), twin: twin || undefined, prefix: prefix || undefined, stream: stream.trim() || undefined, mode, factor: Number(factor) });
      let startError: string | undefined;
      if (start) {
        try {
          await startCosim(String(cosim.id));
        } catch (err) {
          startError = err instanceof Error ? err.message : String(err);
        }
      }
      onCreated(cosim, startError);
    } catch (err) {
      setError(err instanceof Error ? err : new Error(String(err)));
    } finally {
      setBusy(false);
    }
  }

  return (
    <form className="card proc-form" aria-label="New co-simulation" onSubmit={(e) => void submit(e)} noValidate>
      <h3>New co-simulation</h3>
      {error && <ErrorMessage error={error} />}
      <fieldset className="proc-bare" disabled={busy}>
        <div className="proc-basics">
          <PlainField
            id={`${id}-file`}
            label="File"
            path="file"
            required
            error={problems.file}
            hint="A Maestro multi-model (.json), twinlink's YAML form, an SSP archive, or a zip or tar of a document beside its FMUs."
          >
            <input id={`${id}-file`} type="file" accept={ACCEPT} onChange={(e) => chooseFile(e.target.files?.[0] ?? null)} />
          </PlainField>
          <PlainField id={`${id}-name`} label="Name" path="name" required error={problems.name}>
            <input id={`${id}-name`} value={name} required onChange={(e) => setName(e.target.value)} />
          </PlainField>
          <PlainField id={`${id}-twin`} label="Twin" path="twin" hint="Its results go into this twin's history as signals, as they come.">
            <select id={`${id}-twin`} value={twin} onChange={(e) => setTwin(e.target.value)}>
              <option value="">none: results kept here only</option>
              {(twins.data?.items ?? []).map((t) => (
                <option key={t.slug} value={t.slug}>
                  {t.slug}
                </option>
              ))}
            </select>
          </PlainField>
          {twin && (
            <>
              <PlainField id={`${id}-stream`} label="Stream" path="stream" hint="The twin's stream the signals go to; cosim when empty.">
                <input id={`${id}-stream`} value={stream} placeholder="cosim" onChange={(e) => setStream(e.target.value)} />
              </PlainField>
              <PlainField id={`${id}-prefix`} label="Signal prefix" path="prefix" hint="Put before each column's name: sim. makes sim.msd1.m1.x1.">
                <input id={`${id}-prefix`} value={prefix} onChange={(e) => setPrefix(e.target.value)} />
              </PlainField>
            </>
          )}
          <PlainField id={`${id}-mode`} label="Mode" path="mode">
            <select id={`${id}-mode`} value={mode} onChange={(e) => setMode(e.target.value as CosimMode)}>
              <option value="batch">batch: as fast as it goes</option>
              <option value="realtime">real time: paced to the wall clock</option>
            </select>
          </PlainField>
          {mode === "realtime" && (
            <PlainField id={`${id}-factor`} label="Speed factor" path="factor" error={problems.factor} hint="1 is the wall clock, 2 twice as fast.">
              <input id={`${id}-factor`} type="number" min="0" step="any" value={factor} onChange={(e) => setFactor(e.target.value)} />
            </PlainField>
          )}
        </div>
        <label className="sf-check">
          <input type="checkbox" checked={start} onChange={(e) => setStart(e.target.checked)} /> Start it now
        </label>
      </fieldset>
      {twins.error && <p className="muted">The twins cannot be listed ({twins.error.message}): the results stay here.</p>}
      <div className="proc-buttons">
        <button type="submit" disabled={busy}>
          {busy ? "Creating…" : "Create"}
        </button>
        <button type="button" onClick={onCancel} disabled={busy}>
          Cancel
        </button>
      </div>
    </form>
  );
}
