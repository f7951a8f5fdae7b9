import { useEffect, useRef, useState } from "react";

function same(a: unknown, b: unknown): boolean {
  return JSON.stringify(a) === JSON.stringify(b);
}

/** The text of an input that edits a parsed value (a list typed as "a, b", JSON): the text is
 * kept while it is being typed ("a," would otherwise become "a"), and replaced only when the
 * value changes from outside. `edit` sets the text and answers what it parses to, or
 * `undefined` with `ok` false when it does not parse. */
export function useDraft<T>(
  value: T,
  format: (value: T) => string,
  parse: (text: string) => { ok: boolean; value?: T },
): [string, (text: string) => { ok: boolean; value?: T }] {
  const [text, setText] = useState(() => format(value));
  const produced = useRef<unknown>(value);

  useEffect(() => {
    if (!same(value, produced.current)) {
      produced.current = value;
      setText(format(value));
    }
    // format is a pure function of the value; only a new value matters
    // eslint-disable-next-line react-hooks/exhaustive-deps
  }, [value]);

  function edit(next: string) {
    setText(next);
    const parsed = parse(next);
    if (parsed.ok) produced.current = parsed.value;
    return parsed;
  }
  return [text, edit];
}
