// Upload a version of an asset: one file, or a zip/tar archive that is unpacked into the
// version's tree. The File is the request body, so the browser streams it from disk.
import { useId, useState, type FormEvent } from "react";
import { formatOf, KINDS, pushVersion, shortDigest, type PushAnswer, type UploadFormat } from "../../api/library";
import { ErrorMessage } from "../common/Status";
import { PlainField } from "../processors/CreateFields";

export const NAME = /^[a-z0-9][a-z0-9._-]{0,99}$/;
export const TAG = /^[A-Za-z0-9][A-Za-z0-9._+-]{0,63}$/;
const FORMATS: { value: UploadFormat; label: string }[] = [
  { value: "file", label: "one file" },
  { value: "zip", label: "zip archive (unpacked)" },
  { value: "tar", label: "tar archive (unpacked)" },
  { value: "tgz", label: "tar.gz archive (unpacked)" },
];

/** An asset name from a file name: "Tingen Beam.fmu" -> "tingen-beam". */
export function nameFromFile(filename: string): string {
  const stem = filename.replace(/\.(tar\.gz|tgz|zip|tar|fmu|[a-z0-9]{1,5})$/i, "");
  return stem.toLowerCase().replace(/[^a-z0-9._-]+/g, "-").replace(/^[^a-z0-9]+/, "").slice(0, 100);
}

/** The tags typed ("1.0.0, stable"): each checked; `latest` is moved by the server anyway. */
export function parseTags(text: string): { tags: string[]; bad: string | null } {
  const tags = text.split(/[\s,]+/).filter(Boolean);
  const bad = tags.find((t) => !TAG.test(t)) ?? null;
  return { tags: tags.includes("latest") ? tags : ["latest", ...tags], bad };
}

interface Props {
  scopes: string[];
  kind: string;
  onUploaded: (answer: PushAnswer) => void;
}

export function UploadForm({ scopes, kind: initialKind, onUploaded }: Props) {
  const id = useId();
  const [file, setFile] = useState<File | null>(null);
  const [format, setFormat] = useState<UploadFormat>("file");
  const [scope, setScope] = useState(scopes[0] ?? "common");
  const [kind, setKind] = useState(KINDS.includes(initialKind as never) ? initialKind : "data");
  const [name, setName] = useState("");
  const [tagText, setTagText] = useState("");
  const [problems, setProblems] = useState<Record<string, string>>({});
  const [error, setError] = useState<Error | null>(null);
  const [done, setDone] = useState<PushAnswer | null>(null);
  const [busy, setBusy] = useState(false);

  function chooseFile(next: File | null) {
    setFile(next);
    setDone(null);
    if (!next) return;
    setFormat(formatOf(next.name));
    if (!name) setName(nameFromFile(next.name));
  }

  async function submit(event: FormEvent) {
    event.preventDefault();
    const { tags, bad } = parseTags(tagText);
    const found: Record<string, string> = {};
    if (!file) found.file = "choose a file or an archive";
    if (!NAME.test(name)) found.name = "lower case letters, digits, '.', '_' and '-', starting with a letter or digit (at most 100)";
    if (bad) found.tags = `"${bad}" is not a tag: letters, digits, '.', '_', '+' and '-' (at most 64)`;
    setProblems(found);
    if (Object.keys(found).length || !file) return;
    setBusy(true);
    setError(null);
    setDone(null);
    try {
      const answer = await pushVersion({ scope, kind, name, file, format, tags });
      setDone(answer);
      onUploaded(answer);
    } catch (err) {
      setError(err instanceof Error ? err : new Error(String(err)));
    } finally {
      setBusy(false);
    }
  }

  return (
    <form className="card proc-form" aria-label="Upload" onSubmit={(e) => void submit(e)} noValidate>
      <h3>Upload a version</h3>
      {error && <ErrorMessage error={error} />}
      {done && (
        <p className="proc-result" role="status">
          {done.created ? "Uploaded" : "The same content was there already"}: {done.asset.ref} {shortDigest(done.version.digest)} ({done.version.files.length} file
          {done.version.files.length === 1 ? "" : "s"}).
        </p>
      )}
      <fieldset className="proc-bare" disabled={busy}>
        <div className="proc-basics">
          <PlainField id={`${id}-file`} label="File or archive" path="file" required error={problems.file}>
            <input id={`${id}-file`} type="file" onChange={(e) => chooseFile(e.target.files?.[0] ?? null)} />
          </PlainField>
          <PlainField id={`${id}-format`} label="Upload as" path="format" hint="An archive is unpacked into the version's files.">
            <select id={`${id}-format`} value={format} onChange={(e) => setFormat(e.target.value as UploadFormat)}>
              {FORMATS.map((f) => (
                <option key={f.value} value={f.value}>
                  {f.label}
                </option>
              ))}
            </select>
          </PlainField>
          <PlainField id={`${id}-scope`} label="Scope" path="scope" required>
            <select id={`${id}-scope`} value={scope} onChange={(e) => setScope(e.target.value)}>
              {scopes.map((s) => (
                <option key={s} value={s}>
                  {s}
                </option>
              ))}
            </select>
          </PlainField>
          <PlainField id={`${id}-kind`} label="Kind" path="kind" required>
            <select id={`${id}-kind`} value={kind} onChange={(e) => setKind(e.target.value)}>
              {KINDS.map((k) => (
                <option key={k} value={k}>
                  {k}
                </option>
              ))}
            </select>
          </PlainField>
          <PlainField id={`${id}-name`} label="Name" path="name" required error={problems.name} hint="Lower case: letters, digits, '.', '_', '-'.">
            <input id={`${id}-name`} value={name} required onChange={(e) => setName(e.target.value)} />
          </PlainField>
          <PlainField id={`${id}-tags`} label="Tags" path="tags" error={problems.tags} hint="Separated by commas, e.g. 1.0.0; latest is always moved to it.">
            <input id={`${id}-tags`} value={tagText} onChange={(e) => setTagText(e.target.value)} />
          </PlainField>
        </div>
      </fieldset>
      <div className="proc-buttons">
        <button type="submit" disabled={busy}>
          {busy ? "Uploading…" : "Upload"}
        </button>
      </div>
    </form>
  );
}
