// The fallback for anything the form has no input for: the value as JSON text.
import { useEffect, useState } from "react";
import { useFormContext } from "./context";
import { FieldShell, hintText, type FieldProps } from "./fields";
import { useDraft } from "./useDraft";

function parseJson(text: string): { ok: boolean; value?: unknown } {
  if (!text.trim()) return { ok: true, value: undefined };
  try {
    return { ok: true, value: JSON.parse(text) as unknown };
  } catch {
    return { ok: false };
  }
}

export function JsonField({ id, name, label, path, schema, value, onChange, required, nullable }: FieldProps) {
  const { markInvalid } = useFormContext();
  const [bad, setBad] = useState(false);
  const [text, edit] = useDraft<unknown>(value, (v) => (v === undefined ? "" : JSON.stringify(v, null, 2)), parseJson);
  useEffect(() => () => markInvalid(path, false), [markInvalid, path]);

  function change(next: string) {
    const parsed = edit(next);
    setBad(!parsed.ok);
    markInvalid(path, !parsed.ok);
    if (parsed.ok) onChange(parsed.value);
  }
  const hint = [hintText(schema, nullable), "Written as JSON."].filter(Boolean).join(" ");
  return (
    <FieldShell id={id} name={name} label={label} path={path} required={required} hint={hint}>
      <textarea
        id={id}
        className="mono sf-json"
        rows={Math.min(10, Math.max(2, text.split("\n").length))}
        value={text}
        placeholder={schema.default !== undefined ? JSON.stringify(schema.default) : "JSON"}
        aria-invalid={bad ? true : undefined}
        onChange={(e) => change(e.target.value)}
      />
      {bad && <div className="sf-error">This is not valid JSON yet.</div>}
    </FieldShell>
  );
}
