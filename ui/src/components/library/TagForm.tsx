// Point a tag at one of an asset's versions (moving it when it is set elsewhere).
import { useId, useState, type FormEvent } from "react";
import { setTag, shortDigest, type VersionSummary } from "../../api/library";
import { ErrorMessage } from "../common/Status";
import { TAG } from "./UploadForm";

interface Props {
  scope: string;
  kind: string;
  name: string;
  versions: VersionSummary[];
  onDone: () => void;
}

export function TagForm({ scope, kind, name, versions, onDone }: Props) {
  const id = useId();
  const [tag, setTagName] = useState("");
  const [version, setVersion] = useState(versions[0]?.digest ?? "");
  const [error, setError] = useState<Error | null>(null);
  const [busy, setBusy] = useState(false);
  async function submit(event: FormEvent) {
    event.preventDefault();
    if (!TAG.test(tag)) {
      setError(new Error(`"${tag}" is not a tag: letters, digits, '.', '_', '+' and '-' (at most 64), starting with a letter or digit`));
      return;
    }
    setBusy(true);
    setError(null);
    try {
      await setTag(scope, kind, name, tag, version);
      setTagName("");
      onDone();
    } catch (err) {
      setError(err instanceof Error ? err : new Error(String(err)));
    } finally {
      setBusy(false);
    }
  }
  return (
    <form className="dep-actions" aria-label="Set a tag" onSubmit={(e) => void submit(e)} noValidate>
      <label htmlFor={`${id}-tag`}>Tag</label>
      <input id={`${id}-tag`} value={tag} placeholder="1.0.0" onChange={(e) => setTagName(e.target.value)} />
      <label htmlFor={`${id}-version`}>on version</label>
      <select id={`${id}-version`} value={version} onChange={(e) => setVersion(e.target.value)}>
        {versions.map((v) => (
          <option key={v.digest} value={v.digest}>
            {shortDigest(v.digest)}
            {v.tags.length ? ` (${v.tags.join(", ")})` : ""}
          </option>
        ))}
      </select>
      <button type="submit" disabled={busy || !tag}>
        Set tag
      </button>
      {error && <ErrorMessage error={error} />}
    </form>
  );
}
