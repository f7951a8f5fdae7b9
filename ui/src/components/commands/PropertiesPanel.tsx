import { useEffect, useState } from "react";
import { getProperties, patchDesired, type DeviceProperties, type PropertyDecl } from "../../api/commands";
import type { Device } from "../../api/types";
import { useApi } from "../../hooks/useApi";
import { useAction } from "../admin/useAction";
import { Empty, ErrorMessage, Loading, formatTime } from "../common/Status";
import type { FieldValue } from "./commandForm";
import { AddDesiredForm } from "./AddDesiredForm";
import { PropertyTable } from "./PropertyTable";
import { editorValue, propertyRows, toDesired, type PropertyRowData } from "./propertyValues";

interface Props {
  slug: string;
  device: Device;
  decls: PropertyDecl[];
  editable: boolean;
  /** Load the device list again, for its connected state. */
  onRefreshDevice?: () => void;
}

/** The PATCH body of the edited values, or the first value that is not valid. */
/** The edits with `value` for `row`; an edit back to the stored value is no edit. */
function withDraft(drafts: Record<string, FieldValue>, row: PropertyRowData | undefined, name: string, value: FieldValue) {
  const next = { ...drafts, [name]: value };
  if (row && value === editorValue(row)) delete next[name];
  return next;
}

function changesFrom(drafts: Record<string, FieldValue>, decls: PropertyDecl[]): { changes: Record<string, unknown> } | { error: string } {
  const changes: Record<string, unknown> = {};
  for (const [name, value] of Object.entries(drafts)) {
    const converted = toDesired(name, decls.find((d) => d.name === name), value);
    if ("error" in converted) return converted;
    changes[name] = converted.value;
  }
  return { changes };
}

export function ConnectedBadge({ device }: { device: Device }) {
  return device.connected ? <span className="badge badge-ok">connected</span> : <span className="badge">not connected</span>;
}

function DeviceHead({ device, version, onRefresh }: { device: Device; version?: number; onRefresh: () => void }) {
  return (
    <div className="device-head">
      <h3 className="mono">{device.name}</h3>
      <ConnectedBadge device={device} />
      <span className="muted">last seen {formatTime(device.last_seen)}</span>
      {version !== undefined && (
        <span className="muted" data-testid="desired-version">
          desired version {version}
        </span>
      )}
      <button type="button" className="link-button" onClick={onRefresh}>
        Refresh
      </button>
    </div>
  );
}

function SaveBar({ changed, busy, onSave, onDiscard }: { changed: number; busy: boolean; onSave: () => void; onDiscard: () => void }) {
  return (
    <div className="row-actions">
      <button type="submit" onClick={onSave} disabled={busy}>
        {busy ? "Saving…" : `Save ${changed} desired ${changed === 1 ? "value" : "values"}`}
      </button>
      <button type="button" onClick={onDiscard} disabled={busy}>
        Discard
      </button>
    </div>
  );
}

/** One device's reported and desired properties; editors change the desired ones. */
export function PropertiesPanel({ slug, device, decls, editable, onRefreshDevice }: Props) {
  const loaded = useApi((signal) => getProperties(slug, device.name, signal), [slug, device.name]);
  // The answer of the last save holds the new state; a reload replaces it.
  const [saved, setSaved] = useState<DeviceProperties>();
  const [drafts, setDrafts] = useState<Record<string, FieldValue>>({});
  const action = useAction();
  useEffect(() => setSaved(undefined), [loaded.data]);
  const props = saved ?? loaded.data;

  async function patch(changes: Record<string, unknown>) {
    const ok = await action.run(async () => setSaved(await patchDesired(slug, device.name, changes)));
    // Forget the edits that were saved, keep any others.
    if (ok) setDrafts((d) => Object.fromEntries(Object.entries(d).filter(([name]) => !(name in changes))));
    return ok;
  }

  function save() {
    const built = changesFrom(drafts, decls);
    if ("error" in built) action.setError(new Error(built.error));
    else void patch(built.changes);
  }

  const refresh = () => {
    loaded.reload();
    onRefreshDevice?.();
  };
  const header = <DeviceHead device={device} version={props?.version} onRefresh={refresh} />;
  if (loaded.error) return <section className="device-properties">{header}<ErrorMessage error={loaded.error} onRetry={loaded.reload} /></section>;
  if (!props) return <section className="device-properties">{header}<Loading what="Loading properties" /></section>;

  const rows = propertyRows(decls, props);
  const changed = Object.keys(drafts).length;
  return (
    <section className="device-properties" aria-label={`Properties of ${device.name}`}>
      {header}
      {rows.length === 0 ? (
        <Empty>The device has reported no properties and none are desired.</Empty>
      ) : (
        <PropertyTable
          rows={rows}
          declared={decls.length > 0}
          editable={editable}
          busy={action.busy}
          drafts={drafts}
          onDraft={(name, value) => setDrafts((d) => withDraft(d, rows.find((r) => r.name === name), name, value))}
          onRemove={(name) => void patch({ [name]: null })}
        />
      )}
      {editable && changed > 0 && <SaveBar changed={changed} busy={action.busy} onSave={save} onDiscard={() => setDrafts({})} />}
      {editable && decls.length === 0 && <AddDesiredForm busy={action.busy} onAdd={patch} />}
      {action.error && <ErrorMessage error={action.error} />}
      {saved && !action.error && changed === 0 && <p className="doc-ok">Saved: desired version {saved.version}.</p>}
    </section>
  );
}
