import { useState, type FormEvent } from "react";
import type { NewToken } from "../../api/admin";

const DAY = 86_400;
const LIFETIMES: [string, number | undefined][] = [
  ["never expires", undefined],
  ["1 day", DAY],
  ["7 days", 7 * DAY],
  ["30 days", 30 * DAY],
  ["90 days", 90 * DAY],
  ["1 year", 365 * DAY],
];

/** Name and lifetime of a new API token. */
export function CreateTokenForm({ busy, label, onCreate }: { busy: boolean; label: string; onCreate: (token: NewToken) => Promise<boolean> }) {
  const [name, setName] = useState("");
  const [lifetime, setLifetime] = useState(0);

  async function submit(event: FormEvent) {
    event.preventDefault();
    if (!name.trim()) return;
    const expires = LIFETIMES[lifetime]?.[1];
    const token: NewToken = { name: name.trim() };
    if (expires !== undefined) token.expires_in_s = expires;
    if (await onCreate(token)) setName("");
  }

  return (
    <form className="inline-form" onSubmit={(e) => void submit(e)} aria-label={label}>
      <label>
        Token name
        <input value={name} maxLength={128} onChange={(e) => setName(e.target.value)} placeholder="ci job" />
      </label>
      <label>
        Expires
        <select value={lifetime} onChange={(e) => setLifetime(Number(e.target.value))}>
          {LIFETIMES.map(([text], i) => (
            <option key={text} value={i}>
              {text}
            </option>
          ))}
        </select>
      </label>
      <button type="submit" disabled={busy || !name.trim()}>
        Create token
      </button>
    </form>
  );
}
