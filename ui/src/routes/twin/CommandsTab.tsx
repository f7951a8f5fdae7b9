import { useCallback, useMemo, useState } from "react";
import { readInterface, type PropertyDecl } from "../../api/commands";
import { getDeviceList } from "../../api/twins";
import type { Device } from "../../api/types";
import { CommandCard } from "../../components/commands/CommandCard";
import { CommandLog } from "../../components/commands/CommandLog";
import { FreeCommandForm } from "../../components/commands/FreeCommandForm";
import { PropertiesPanel } from "../../components/commands/PropertiesPanel";
import { CHOOSE_DEVICE, preselectDevice } from "../../components/commands/deviceChoice";
import { SendOptions } from "../../components/commands/SendOptions";
import type { SendTarget } from "../../components/commands/useSendCommand";
import { Empty, ErrorMessage, Loading } from "../../components/common/Status";
import { useApi, type ApiState } from "../../hooks/useApi";
import "../../components/commands/commands.css";
import { canEdit, useTwin } from "./context";

function DeviceNotes({ devices, editable }: { devices: Device[] | undefined; editable: boolean }) {
  return (
    <>
      {!editable && (
        <p className="notice">You can see the commands and properties of this twin, but sending commands and changing desired values needs the editor role.</p>
      )}
      {devices && devices.length === 0 && (
        <p className="notice">This twin has no devices, so a command has nowhere to go. Add a device on the Overview tab.</p>
      )}
    </>
  );
}

interface PropertiesSectionProps {
  slug: string;
  devices: ApiState<Device[]>;
  decls: PropertyDecl[];
  editable: boolean;
}

function PropertiesSection({ slug, devices, decls, editable }: PropertiesSectionProps) {
  if (devices.error) return <ErrorMessage error={devices.error} onRetry={devices.reload} />;
  if (!devices.data) return <Loading what="Loading devices" />;
  if (devices.data.length === 0) return <Empty>No devices, so no properties.</Empty>;
  return (
    <>
      {devices.data.map((d) => (
        <PropertiesPanel key={d.name} slug={slug} device={d} decls={decls} editable={editable} onRefreshDevice={devices.reload} />
      ))}
    </>
  );
}

/** Commands from the twin's interface with their results, the command log, and each
 * device's reported and desired properties. */
export function CommandsTab() {
  const { slug, twin } = useTwin();
  const editable = canEdit(twin);
  const { commands, properties, defaultDevice } = useMemo(() => readInterface(twin.document), [twin.document]);
  const list = useApi((signal) => getDeviceList(slug, signal), [slug]);
  const devices: ApiState<Device[]> = { ...list, data: list.data?.devices };
  const [target, setTarget] = useState<SendTarget>({ queue: false });
  const [logKey, setLogKey] = useState(0);
  const onSent = useCallback(() => setLogKey((k) => k + 1), []);

  // The device chosen in the list, else the one a command naming none would go to.
  const known = devices.data ?? [];
  const chosen = target.device && known.some((d) => d.name === target.device) ? target.device : undefined;
  const device = chosen ?? preselectDevice(known, defaultDevice, list.data?.default_device);
  const missing = known.length > 1 && !device ? CHOOSE_DEVICE : undefined;
  const effective: SendTarget = { ...target, device, missing };
  const disabled = !editable;
  return (
    <>
      <h2>Commands</h2>
      <DeviceNotes devices={devices.data} editable={editable} />
      <SendOptions devices={known} target={effective} disabled={disabled} onChange={setTarget} />
      <div className="command-cards">
        {commands.map((c) => (
          <CommandCard key={c.name} slug={slug} command={c} target={effective} disabled={disabled} onSent={onSent} />
        ))}
        {commands.length === 0 && <FreeCommandForm slug={slug} target={effective} disabled={disabled} onSent={onSent} />}
      </div>

      <h2>Command log</h2>
      <CommandLog slug={slug} refreshKey={logKey} />

      <h2>Properties</h2>
      <PropertiesSection slug={slug} devices={devices} decls={properties} editable={editable} />
    </>
  );
}
