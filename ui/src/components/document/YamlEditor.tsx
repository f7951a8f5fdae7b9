import { forwardRef, useImperativeHandle, useMemo, useRef, type UIEvent } from "react";
import type { DocumentProblem } from "../../api/documents";
import "./document.css";

export interface YamlEditorHandle {
  /** Put the cursor at the start of `line` (from 1) and scroll it into view. */
  goToLine: (line: number) => void;
}

interface Props {
  value: string;
  onChange: (value: string) => void;
  problems: DocumentProblem[];
  readOnly?: boolean;
  label: string;
}

const LINE_HEIGHT_EM = 1.5;

/** A plain-text YAML editor with line numbers; lines with problems are marked in the gutter
 * (hover for the message). A textarea keeps native editing, undo and accessibility. */
export const YamlEditor = forwardRef<YamlEditorHandle, Props>(function YamlEditor(
  { value, onChange, problems, readOnly = false, label },
  ref,
) {
  const area = useRef<HTMLTextAreaElement>(null);
  const gutter = useRef<HTMLDivElement>(null);
  const lineCount = useMemo(() => value.split("\n").length, [value]);
  const byLine = useMemo(() => {
    const map = new Map<number, string[]>();
    for (const p of problems) {
      if (!p.line) continue;
      map.set(p.line, [...(map.get(p.line) ?? []), p.path ? `${p.path}: ${p.message}` : p.message]);
    }
    return map;
  }, [problems]);

  useImperativeHandle(ref, () => ({
    goToLine(line: number) {
      const el = area.current;
      if (!el) return;
      const lines = el.value.split("\n");
      const offset = lines.slice(0, Math.max(0, line - 1)).reduce((sum, l) => sum + l.length + 1, 0);
      el.focus();
      el.setSelectionRange(offset, offset + (lines[line - 1]?.length ?? 0));
      const lineHeight = parseFloat(getComputedStyle(el).fontSize || "14") * LINE_HEIGHT_EM;
      el.scrollTop = Math.max(0, (line - 4) * lineHeight);
    },
  }));

  const syncScroll = (event: UIEvent<HTMLTextAreaElement>) => {
    if (gutter.current) gutter.current.scrollTop = event.currentTarget.scrollTop;
  };

  return (
    <div className="yaml-editor">
      <div className="yaml-gutter" ref={gutter} aria-hidden="true">
        {Array.from({ length: lineCount }, (_, i) => {
          const messages = byLine.get(i + 1);
          return (
            <div
              key={i}
              className={messages ? "yaml-line yaml-line-bad" : "yaml-line"}
              title={messages?.join("\n")}
              data-error-line={messages ? i + 1 : undefined}
            >
              {i + 1}
            </div>
          );
        })}
      </div>
      <textarea
        ref={area}
        className="yaml-text"
        aria-label={label}
        value={value}
        readOnly={readOnly}
        spellCheck={false}
        wrap="off"
        onChange={(e) => onChange(e.target.value)}
        onScroll={syncScroll}
      />
    </div>
  );
});
