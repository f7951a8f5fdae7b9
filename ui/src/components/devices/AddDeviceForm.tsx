import { useState, type FormEvent } from "react";

const DEVICE_NAME = /^[A-Za-z0-9._:-]{1,64}$/;

/** Name and description of a new device. */
export function AddDeviceForm({ busy, onAdd }: { busy: boolean; onAdd: (name: string, description: string) => Promise<boolean> }) {
  const [name, setName] = useState("");
  const [description, setDescription] = useState("");
  const valid = DEVICE_NAME.test(name);

  async function submit(event: FormEvent) {
    event.preventDefault();
    if (!valid) return;
    if (await onAdd(name, description)) {
      setName("");
      setDescription("");
    }
  }

  return (
    <form className="inline-form" onSubmit={(e) => void submit(e)} aria-label="Add a device">
      <label>
        Device name
        <input className="mono" value={name} onChange={(e) => setName(e.target.value)} placeholder="tingenSAP" maxLength={64} />
      </label>
      <label>
        Description
        <input value={description} onChange={(e) => setDescription(e.target.value)} placeholder="the rig's Raspberry Pi" maxLength={2000} />
      </label>
      <button type="submit" disabled={busy || !valid}>
        Add device
      </button>
      {name && !valid && <span className="muted">1-64 letters, digits and . _ : -</span>}
    </form>
  );
}
