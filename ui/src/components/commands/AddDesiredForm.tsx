import { useState, type FormEvent } from "react";
import { parseLoose } from "./propertyValues";

/** Set a desired value of a new name (only when the interface declares no properties). */
export function AddDesiredForm({ busy, onAdd }: { busy: boolean; onAdd: (changes: Record<string, unknown>) => Promise<boolean> }) {
  const [name, setName] = useState("");
  const [value, setValue] = useState("");

  async function submit(event: FormEvent) {
    event.preventDefault();
    if (!name.trim() || !value.trim()) return;
    if (await onAdd({ [name.trim()]: parseLoose(value) })) {
      setName("");
      setValue("");
    }
  }

  return (
    <form className="add-desired" onSubmit={(e) => void submit(e)} aria-label="Add a desired property">
      <input className="mono" aria-label="New property name" placeholder="property name" value={name} onChange={(e) => setName(e.target.value)} />
      <input className="mono" aria-label="New property value" placeholder='50, true or "text"' value={value} onChange={(e) => setValue(e.target.value)} />
      <button type="submit" disabled={busy || !name.trim() || !value.trim()}>
        Set desired
      </button>
    </form>
  );
}
