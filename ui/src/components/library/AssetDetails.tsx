// One asset: its metadata, its versions with their tags, a version's files, download as an
// archive, and deleting a version (refused, with the reason, while a deployment holds it).
import { useState } from "react";
import {
  deleteAsset,
  deleteTag,
  deleteVersion,
  downloadArchive,
  formatBytes,
  getAsset,
  getVersion,
  shortDigest,
  type ArchiveFormat,
  type AssetDetails as AssetDetailsAnswer,
  type VersionSummary,
} from "../../api/library";
import { useApi } from "../../hooks/useApi";
import { ErrorMessage, Loading } from "../common/Status";
import { formatEpochMs } from "../common/time";
import { TagForm } from "./TagForm";

interface Props {
  scope: string;
  kind: string;
  name: string;
  /** Told when a version was deleted (the list's counts change). */
  onChanged: () => void;
  /** Told when the whole asset was deleted. */
  onDeleted: () => void;
}

function Files({ scope, kind, name, digest }: { scope: string; kind: string; name: string; digest: string }) {
  const version = useApi((signal) => getVersion(scope, kind, name, digest, signal), [scope, kind, name, digest]);
  if (version.error) return <ErrorMessage error={version.error} onRetry={version.reload} />;
  if (!version.data) return <Loading what="Loading the files" />;
  return (
    <table className="table entry-table" aria-label={`Files of ${shortDigest(digest)}`}>
      <tbody>
        {version.data.files.map((f) => (
          <tr key={f.path}>
            <td className="mono">
              {f.path}
              {f.executable && <span className="badge">executable</span>}
            </td>
            <td className="num">{formatBytes(f.size)}</td>
            <td className="mono muted" title={f.sha256}>
              {f.sha256.slice(0, 12)}
            </td>
          </tr>
        ))}
      </tbody>
    </table>
  );
}

function VersionRow({ v, open, onToggle, onDownload, onDelete, onUntag }: {
  v: VersionSummary;
  open: boolean;
  onToggle: () => void;
  onDownload: (format: ArchiveFormat) => void;
  onDelete: () => void;
  onUntag: (tag: string) => void;
}) {
  const short = shortDigest(v.digest);
  return (
    <tr className={open ? "proc-row-open" : undefined}>
      <td className="mono" title={v.digest}>
        {short}
      </td>
      <td>
        {v.tags.length ? (
          v.tags.map((t) => (
            <span key={t} className="chip">
              {t}
              <button type="button" className="link-button chip-remove" aria-label={`Remove tag ${t}`} title="Remove the tag (the version stays)" onClick={() => onUntag(t)}>
                ×
              </button>
            </span>
          ))
        ) : (
          <span className="muted">none</span>
        )}
      </td>
      <td className="num">{formatBytes(v.size)}</td>
      <td>{formatEpochMs(v.created_ns / 1e6)}</td>
      <td>{v.created_by}</td>
      <td className="nowrap">
        <button type="button" className="link-button" aria-expanded={open} aria-label={`Files of ${short}`} onClick={onToggle}>
          Files
        </button>
        <button type="button" className="link-button" aria-label={`Download ${short} as zip`} onClick={() => onDownload("zip")}>
          zip
        </button>
        <button type="button" className="link-button" aria-label={`Download ${short} as tar.gz`} onClick={() => onDownload("tgz")}>
          tar.gz
        </button>
        <button type="button" className="link-button proc-danger" aria-label={`Delete ${short}`} onClick={onDelete}>
          Delete
        </button>
      </td>
    </tr>
  );
}

/** What the asset says of itself: its reference, author, licence and keywords. */
function AssetMeta({ a }: { a: AssetDetailsAnswer }) {
  return (
    <dl className="props">
      <dt>Reference</dt>
      <dd className="mono">lib:{a.ref}@latest</dd>
      {a.author && (
        <>
          <dt>Author</dt>
          <dd>{a.author}</dd>
        </>
      )}
      {a.licence && (
        <>
          <dt>Licence</dt>
          <dd>{a.licence}</dd>
        </>
      )}
      {a.keywords.length > 0 && (
        <>
          <dt>Keywords</dt>
          <dd>{a.keywords.map((k) => <span key={k} className="chip">{k}</span>)}</dd>
        </>
      )}
    </dl>
  );
}

interface VersionsProps {
  versions: VersionSummary[];
  open: string | null;
  onToggle: (digest: string) => void;
  onDownload: (digest: string, format: ArchiveFormat) => void;
  onDelete: (v: VersionSummary) => void;
  onUntag: (tag: string) => void;
}

function VersionsTable({ versions, open, onToggle, onDownload, onDelete, onUntag }: VersionsProps) {
  return (
    <div className="table-scroll">
      <table className="table" aria-label="Versions">
        <thead>
          <tr>
            <th>Version</th>
            <th>Tags</th>
            <th className="num">Size</th>
            <th>Pushed</th>
            <th>By</th>
            <th>
              <span className="visually-hidden">Actions</span>
            </th>
          </tr>
        </thead>
        <tbody>
          {versions.map((v) => (
            <VersionRow
              key={v.digest}
              v={v}
              open={open === v.digest}
              onToggle={() => onToggle(v.digest)}
              onDownload={(format) => onDownload(v.digest, format)}
              onDelete={() => onDelete(v)}
              onUntag={onUntag}
            />
          ))}
        </tbody>
      </table>
    </div>
  );
}

export function AssetDetails({ scope, kind, name, onChanged, onDeleted }: Props) {
  const asset = useApi((signal) => getAsset(scope, kind, name, signal), [scope, kind, name]);
  const [open, setOpen] = useState<string | null>(null);
  const [error, setError] = useState<Error | null>(null);
  async function attempt(fn: () => Promise<void>) {
    setError(null);
    try {
      await fn();
    } catch (err) {
      setError(err instanceof Error ? err : new Error(String(err)));
    }
  }
  function remove(v: VersionSummary) {
    if (!window.confirm(`Delete version ${shortDigest(v.digest)} of ${scope}/${kind}/${name}? It cannot be undone.`)) return;
    void attempt(async () => {
      await deleteVersion(scope, kind, name, v.digest);
      asset.reload();
      onChanged();
    });
  }
  function removeAsset() {
    if (!window.confirm(`Delete ${scope}/${kind}/${name} with all its versions and tags? It cannot be undone.`)) return;
    void attempt(async () => {
      await deleteAsset(scope, kind, name);
      onDeleted();
    });
  }
  if (asset.error && !asset.data) return <ErrorMessage error={asset.error} onRetry={asset.reload} />;
  if (!asset.data) return <Loading />;
  const a = asset.data;
  return (
    <section className="card" aria-label={`Asset ${a.ref}`}>
      <div className="dep-toolbar">
        <h2>{a.ref}</h2>
        <span className="spacer" />
        <button type="button" className="proc-danger" onClick={removeAsset}>
          Delete asset
        </button>
      </div>
      {a.description && <p>{a.description}</p>}
      <AssetMeta a={a} />
      {error && <ErrorMessage error={error} />}
      <VersionsTable
        versions={a.versions}
        open={open}
        onToggle={(digest) => setOpen(open === digest ? null : digest)}
        onDownload={(digest, format) => void attempt(() => downloadArchive(scope, kind, name, digest, format))}
        onDelete={remove}
        onUntag={(tag) =>
          void attempt(async () => {
            await deleteTag(scope, kind, name, tag);
            asset.reload();
            onChanged();
          })
        }
      />
      {open && <Files scope={scope} kind={kind} name={name} digest={open} />}
      {a.versions.length > 0 && (
        <TagForm
          scope={scope}
          kind={kind}
          name={name}
          versions={a.versions}
          onDone={() => {
            asset.reload();
            onChanged();
          }}
        />
      )}
    </section>
  );
}
