import type { Device } from "../../api/types";
import type { SendTarget } from "./useSendCommand";

interface Props {
  devices: Device[];
  target: SendTarget;
  disabled: boolean;
  onChange: (target: SendTarget) => void;
}

/** The device to send to (when there are several), the timeout and whether to queue. */
export function SendOptions({ devices, target, disabled, onChange }: Props) {
  return (
    <div className="send-options">
      {devices.length > 1 && (
        <label>
          Device{" "}
          <select value={target.device ?? ""} disabled={disabled} onChange={(e) => onChange({ ...target, device: e.target.value || undefined })}>
            {/* Only when nothing could be preselected: there is then no sensible default. */}
            {!target.device && (
              <option value="" disabled>
                choose a device
              </option>
            )}
            {devices.map((d) => (
              <option key={d.name} value={d.name}>
                {d.name}
                {d.connected ? " (connected)" : ""}
              </option>
            ))}
          </select>
        </label>
      )}
      <label>
        Timeout (s){" "}
        <input
          type="number"
          min={1}
          step="any"
          className="timeout-input"
          placeholder="default"
          disabled={disabled}
          value={target.timeoutS ?? ""}
          onChange={(e) => onChange({ ...target, timeoutS: e.target.value === "" ? undefined : Number(e.target.value) })}
        />
      </label>
      <label title="When the device is offline, keep the command and send it when the device connects, until it expires.">
        <input type="checkbox" checked={target.queue} disabled={disabled} onChange={(e) => onChange({ ...target, queue: e.target.checked })} /> Queue
        for an offline device
      </label>
    </div>
  );
}
