import { Fragment } from "react";

/** The places a signal name may break over two lines: after `_ . - / :` and between a small
 * letter or digit and a capital ("tipAngle"), never inside a word. */
export function nameParts(name: string): string[] {
  return name.split(/(?<=[_.\-/:])|(?<=[a-z0-9])(?=[A-Z])/).filter((part) => part !== "");
}

/** A long identifier (`Tip_Angular_Rate_Y_radps`) that wraps only between its words. */
export function WordBreaks({ text }: { text: string }) {
  const parts = nameParts(text);
  return (
    <>
      {parts.map((part, i) => (
        <Fragment key={i}>
          {i > 0 && <wbr />}
          {part}
        </Fragment>
      ))}
    </>
  );
}
