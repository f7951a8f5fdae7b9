import { useState } from "react";
import { createDevice, deleteDevice, rotateDeviceToken, type DeviceWithToken } from "../../api/admin";
import { listDevices } from "../../api/twins";
import type { Device } from "../../api/types";
import { useApi } from "../../hooks/useApi";
import { SecretOnce } from "../admin/SecretOnce";
import { useAction } from "../admin/useAction";
import { Empty, ErrorMessage, Loading, formatTime } from "../common/Status";
import { AddDeviceForm } from "./AddDeviceForm";

interface RowProps {
  device: Device;
  canEdit: boolean;
  busy: boolean;
  onRotate: (d: Device) => void;
  onDelete: (d: Device) => void;
}

function DeviceRow({ device: d, canEdit, busy, onRotate, onDelete }: RowProps) {
  return (
    <tr>
      <td className="mono">{d.name}</td>
      <td>{d.description ?? ""}</td>
      <td>{d.connected ? <span className="badge badge-ok">connected</span> : <span className="badge">no</span>}</td>
      <td>{formatTime(d.last_seen)}</td>
      <td className="mono">{d.token_prefix ? `${d.token_prefix}…` : ""}</td>
      {canEdit && (
        <td className="row-actions">
          <button type="button" disabled={busy} onClick={() => onRotate(d)}>
            New token
          </button>
          <button type="button" className="danger" disabled={busy} onClick={() => onDelete(d)}>
            Delete
          </button>
        </td>
      )}
    </tr>
  );
}

function DeviceTable({ devices, ...rest }: { devices: Device[] } & Omit<RowProps, "device">) {
  return (
    <div className="table-scroll">
      <table className="table">
        <thead>
          <tr>
            <th>Device</th>
            <th>Description</th>
            <th>Connected</th>
            <th>Last seen</th>
            <th>Token</th>
            {rest.canEdit && <th aria-label="Actions" />}
          </tr>
        </thead>
        <tbody>
          {devices.map((d) => (
            <DeviceRow key={d.name} device={d} {...rest} />
          ))}
        </tbody>
      </table>
    </div>
  );
}

/** A twin's devices; editors add them, replace their tokens and delete them. A new token is
 * shown once, from component state only. */
export function DevicesSection({ slug, canEdit }: { slug: string; canEdit: boolean }) {
  const devices = useApi((signal) => listDevices(slug, signal), [slug]);
  const [issued, setIssued] = useState<{ title: string; device: DeviceWithToken }>();
  const action = useAction();

  const add = (name: string, description: string) =>
    action.run(async () => {
      const device = await createDevice(slug, name, description);
      setIssued({ title: `Token of the new device ${device.name}`, device });
      devices.reload();
    });
  const rotate = (d: Device) => {
    if (!window.confirm(`Give ${d.name} a new token? Its current token stops working at once.`)) return;
    void action.run(async () => {
      const device = await rotateDeviceToken(slug, d.name);
      setIssued({ title: `New token of ${device.name}`, device });
      devices.reload();
    });
  };
  const remove = (d: Device) => {
    if (!window.confirm(`Delete the device ${d.name}? Its token stops working at once.`)) return;
    void action.run(async () => {
      await deleteDevice(slug, d.name);
      setIssued((i) => (i?.device.name === d.name ? undefined : i));
      devices.reload();
    });
  };

  return (
    <>
      <h2>Devices</h2>
      {issued && <SecretOnce title={issued.title} secret={issued.device.token} onDone={() => setIssued(undefined)} />}
      {action.error && <ErrorMessage error={action.error} />}
      {devices.error ? (
        <ErrorMessage error={devices.error} onRetry={devices.reload} />
      ) : devices.loading && !devices.data ? (
        <Loading />
      ) : devices.data && devices.data.length > 0 ? (
        <DeviceTable devices={devices.data} canEdit={canEdit} busy={action.busy} onRotate={rotate} onDelete={remove} />
      ) : (
        <Empty>This twin has no devices.</Empty>
      )}
      {canEdit && <AddDeviceForm busy={action.busy} onAdd={add} />}
    </>
  );
}
