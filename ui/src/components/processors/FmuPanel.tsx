// The twin's uploaded FMUs: the list, each one's variables, and an upload for editors.
import { useState, type FormEvent } from "react";
import { ApiError } from "../../api/client";
import { getFmu, listFmus, uploadFmu, type Fmu } from "../../api/processors";
import { useApi } from "../../hooks/useApi";
import { Empty, ErrorMessage, Loading } from "../common/Status";
import { FmuVariables } from "./FmuVariables";
import { formatNs } from "./format";
import "./processors.css";

interface Props {
  slug: string;
  editable: boolean;
  /** Changes when an FMU was uploaded here (or elsewhere), to load the list again. */
  version: number;
  onUploaded: (fmu: Fmu) => void;
}

export function FmuPanel({ slug, editable, version, onUploaded }: Props) {
  const fmus = useApi((signal) => listFmus(slug, signal), [slug, version]);
  const [open, setOpen] = useState<string | null>(null);
  return (
    <section className="proc-fmus" aria-label="FMUs">
      <h3>FMUs</h3>
      <p className="muted">Functional Mock-up Units uploaded to this twin, for processors of the blueprint fmu.</p>
      {editable && <FmuUpload slug={slug} onUploaded={onUploaded} />}
      {fmus.error && <ErrorMessage error={fmus.error} onRetry={fmus.reload} />}
      {!fmus.data && !fmus.error && <Loading what="Loading FMUs" />}
      {fmus.data?.length === 0 && <Empty>No FMU uploaded yet.</Empty>}
      {fmus.data && fmus.data.length > 0 && (
        <table className="table" aria-label="Uploaded FMUs">
          <thead>
            <tr>
              <th>File</th>
              <th>Model</th>
              <th>FMI</th>
              <th className="num">Size</th>
              <th>Uploaded</th>
              <th />
            </tr>
          </thead>
          <tbody>
            {fmus.data.map((f) => (
              <tr key={f.name}>
                <td className="mono">{f.name}</td>
                <td>{f.model_name ?? ""}</td>
                <td>{f.fmi_version ?? ""}</td>
                <td className="num">{(f.size / 1024).toFixed(1)} KB</td>
                <td>{formatNs(f.uploaded_ns)}</td>
                <td>
                  <button type="button" className="link-button" aria-expanded={open === f.name} onClick={() => setOpen(open === f.name ? null : f.name)}>
                    {open === f.name ? "Hide variables" : `Variables of ${f.name}`}
                  </button>
                </td>
              </tr>
            ))}
          </tbody>
        </table>
      )}
      {open && <FmuDetail slug={slug} name={open} />}
    </section>
  );
}

function FmuDetail({ slug, name }: { slug: string; name: string }) {
  const fmu = useApi((signal) => getFmu(slug, name, signal), [slug, name]);
  if (fmu.error) return <ErrorMessage error={fmu.error} onRetry={fmu.reload} />;
  if (!fmu.data) return <Loading what="Loading the FMU" />;
  return (
    <div className="card">
      <h4>
        {name} <span className="muted">{fmu.data.description ?? ""}</span>
      </h4>
      <FmuVariables variables={fmu.data.variables ?? []} caption={`Variables of ${name}`} />
    </div>
  );
}

/** An upload's failure with what it means: too large (413), not usable (422), not allowed (403). */
function uploadError(err: unknown): Error {
  if (!(err instanceof ApiError)) return err instanceof Error ? err : new Error(String(err));
  const why: Record<number, string> = {
    413: "The file is larger than this server accepts",
    422: "The server cannot use this file",
    403: "You may not upload FMUs here",
  };
  const lead = why[err.status];
  return lead ? new ApiError(err.status, `${lead}: ${err.detail}`, err.problem) : err;
}

function FmuUpload({ slug, onUploaded }: { slug: string; onUploaded: (fmu: Fmu) => void }) {
  const [file, setFile] = useState<File | null>(null);
  const [name, setName] = useState("");
  const [busy, setBusy] = useState(false);
  const [error, setError] = useState<Error>();
  const [done, setDone] = useState<string | null>(null);

  async function upload(event: FormEvent) {
    event.preventDefault();
    if (!file) return;
    setBusy(true);
    setError(undefined);
    setDone(null);
    try {
      const made = await uploadFmu(slug, name.trim() || file.name, file);
      const count = (causality: string) => {
        const n = (made.variables ?? []).filter((v) => v.causality === causality).length;
        return `${n} ${causality}${n === 1 ? "" : "s"}`;
      };
      const parts = [count("input"), count("output"), count("parameter")].join(", ");
      setDone(`Uploaded ${made.name}: FMI ${made.fmi_version ?? "?"}, ${parts}.`);
      onUploaded(made);
    } catch (err) {
      setError(uploadError(err));
    } finally {
      setBusy(false);
    }
  }

  return (
    <form className="proc-upload" aria-label="Upload an FMU" onSubmit={(e) => void upload(e)}>
      <label>
        FMU file{" "}
        <input
          type="file"
          accept=".fmu"
          onChange={(e) => {
            const chosen = e.target.files?.[0] ?? null;
            setFile(chosen);
            setName(chosen?.name ?? "");
          }}
        />
      </label>
      <label>
        Save as <input className="mono" value={name} placeholder="Model.fmu" onChange={(e) => setName(e.target.value)} />
      </label>
      <button type="submit" disabled={!file || busy}>
        {busy ? "Uploading…" : "Upload FMU"}
      </button>
      {done && (
        <span className="proc-result" role="status">
          {done}
        </span>
      )}
      {error && <ErrorMessage error={error} />}
    </form>
  );
}
