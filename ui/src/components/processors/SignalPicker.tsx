interface Props {
  label: string;
  value: string;
  /** The source stream's signals; none known (no data stored yet): a text input instead. */
  signals: string[];
  /** The text of the empty choice. */
  none: string;
  onChange: (signal: string) => void;
  id?: string;
}

/** Choose a signal of the source stream. */
export function SignalPicker({ label, value, signals, none, onChange, id }: Props) {
  if (!signals.length) {
    return <input id={id} aria-label={label} className="mono" placeholder="signal name" value={value} onChange={(e) => onChange(e.target.value)} />;
  }
  // A signal set before (or typed elsewhere) stays a choice even if the stream lacks it.
  const options = value && !signals.includes(value) ? [value, ...signals] : signals;
  return (
    <select id={id} aria-label={label} value={value} onChange={(e) => onChange(e.target.value)}>
      <option value="">{none}</option>
      {options.map((s) => (
        <option key={s} value={s}>
          {s}
        </option>
      ))}
    </select>
  );
}
