import { useState } from "react";
import { downloadTwinExport, TWIN_EXPORTS, type TwinExportFormat } from "../../api/exports";
import { ErrorMessage } from "../common/Status";

const FORMATS = Object.keys(TWIN_EXPORTS) as TwinExportFormat[];

/** Download buttons for the twin's document: as YAML or JSON, or converted by the server to a
 * WoT Thing Description, a DTDL Interface, or an Asset Administration Shell (JSON or AASX).
 * Each export holds what the signed-in user may read of the document. */
export function ExportButtons({ slug }: { slug: string }) {
  const [busy, setBusy] = useState<TwinExportFormat | null>(null);
  const [error, setError] = useState<Error>();
  const [saved, setSaved] = useState<string>();
  const download = async (format: TwinExportFormat) => {
    setBusy(format);
    setError(undefined);
    setSaved(undefined);
    try {
      setSaved(await downloadTwinExport(slug, format));
    } catch (err) {
      setError(err instanceof Error ? err : new Error(String(err)));
    } finally {
      setBusy(null);
    }
  };
  return (
    <div className="toolbar" role="group" aria-label="Download the document">
      <span className="muted">Download:</span>
      {FORMATS.map((format) => (
        <button key={format} type="button" disabled={busy !== null} onClick={() => void download(format)}>
          {busy === format ? "Downloading…" : TWIN_EXPORTS[format].label}
        </button>
      ))}
      {saved && (
        <span className="muted" role="status">
          Saved {saved}
        </span>
      )}
      {error && <ErrorMessage error={error} />}
    </div>
  );
}
