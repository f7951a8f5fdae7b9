import { useEffect, useRef, useState } from "react";
import { documentProblems, getPartYaml, listParts, putDocument, type DocumentProblem } from "../../api/documents";
import { Empty, ErrorMessage, Loading } from "../../components/common/Status";
import { YamlEditor, type YamlEditorHandle } from "../../components/document/YamlEditor";
import { useApi } from "../../hooks/useApi";
import { useDebounced } from "../../hooks/useDebounced";
import { canEdit, useTwin } from "./context";

type Check =
  | { kind: "idle" }
  | { kind: "checking" }
  | { kind: "ok"; outcome: string }
  | { kind: "problems"; problems: DocumentProblem[]; detail: string }
  | { kind: "error"; error: Error };

/** Turn a refused PUT into what the editor shows: problems at their lines, or a plain error. */
function checkOf(error: unknown): Check {
  const problems = documentProblems(error);
  if (problems.length > 0) return { kind: "problems", problems, detail: (error as Error).message };
  return { kind: "error", error: error instanceof Error ? error : new Error(String(error)) };
}

/** The twin's DT document, one privacy part at a time, as YAML: read, check as you type, save. */
export function DocumentTab() {
  const { slug, twin, reload } = useTwin();
  const editable = canEdit(twin);
  const levels = useApi((signal) => listParts(slug, signal), [slug]);
  const [level, setLevel] = useState<string>();
  const chosen = level ?? levels.data?.[levels.data.length - 1];
  const part = useApi((signal) => (chosen ? getPartYaml(slug, chosen, signal) : Promise.resolve("")), [slug, chosen]);
  const [text, setText] = useState("");
  // The text the editor was loaded with; undefined until the part has arrived.
  const [base, setBase] = useState<string>();
  const [check, setCheck] = useState<Check>({ kind: "idle" });
  const [saved, setSaved] = useState<string>();
  const [saving, setSaving] = useState(false);
  const editor = useRef<YamlEditorHandle>(null);
  const dirty = base !== undefined && text !== base;
  const typed = useDebounced(text, 600);

  useEffect(() => {
    if (part.data !== undefined) {
      setText(part.data);
      setBase(part.data);
      setCheck({ kind: "idle" });
    }
  }, [part.data]);

  // Check the edit on the server (a dry run) once typing pauses.
  useEffect(() => {
    // Only a settled edit of the loaded text is checked.
    if (!editable || base === undefined || typed !== text || typed === base) return;
    const controller = new AbortController();
    setCheck({ kind: "checking" });
    putDocument(slug, typed, true, controller.signal).then(
      (answer) => setCheck({ kind: "ok", outcome: answer.outcome }),
      (error: unknown) => {
        if (!controller.signal.aborted) setCheck(checkOf(error));
      },
    );
    return () => controller.abort();
  }, [typed, text, editable, slug, base]);

  const save = async () => {
    setSaving(true);
    setSaved(undefined);
    try {
      const answer = await putDocument(slug, text, false);
      setSaved(answer.outcome === "unchanged" ? "Nothing to save: the part is unchanged." : "Saved.");
      setCheck({ kind: "idle" });
      part.reload();
      reload();
    } catch (error) {
      setCheck(checkOf(error));
    } finally {
      setSaving(false);
    }
  };

  if (levels.error) return <ErrorMessage error={levels.error} onRetry={levels.reload} />;
  if (!levels.data) return <Loading what="Loading the document's parts" />;
  if (levels.data.length === 0) return <Empty>You may not see any part of this twin's document.</Empty>;

  const problems = check.kind === "problems" ? check.problems : [];
  return (
    <section aria-label="DT document">
      <div className="doc-toolbar">
        <label>
          Part{" "}
          <select value={chosen} onChange={(e) => setLevel(e.target.value)} disabled={dirty}>
            {levels.data.map((lv) => (
              <option key={lv} value={lv}>
                {lv}
              </option>
            ))}
          </select>
        </label>
        <CheckStatus check={check} dirty={dirty} editable={editable} />
        <span className="spacer" />
        {editable && (
          <>
            <button type="button" disabled={!dirty || saving} onClick={() => setText(base ?? "")}>
              Revert
            </button>
            <button type="submit" disabled={!dirty || saving || check.kind === "problems"} onClick={() => void save()}>
              {saving ? "Saving…" : "Save"}
            </button>
          </>
        )}
      </div>
      {!editable && <p className="muted">Read only: changing the document needs the editor role.</p>}
      {saved && !dirty && <p className="doc-ok" role="status">{saved}</p>}
      {part.error ? (
        <ErrorMessage error={part.error} onRetry={part.reload} />
      ) : part.data === undefined ? (
        <Loading what="Loading the part" />
      ) : (
        <YamlEditor ref={editor} label={`YAML of the ${chosen} part`} value={text} onChange={setText} problems={problems} readOnly={!editable} />
      )}
      {check.kind === "error" && <ErrorMessage error={check.error} />}
      {check.kind === "problems" && (
        <ul className="doc-problems" aria-label="Problems">
          {check.problems.map((p, i) => (
            <li key={i}>
              <button type="button" onClick={() => p.line && editor.current?.goToLine(p.line)}>
                {p.line ? `Line ${p.line}${p.column ? `, column ${p.column}` : ""}: ` : ""}
                {p.path ? `${p.path}: ` : ""}
                {p.message}
              </button>
            </li>
          ))}
        </ul>
      )}
    </section>
  );
}

function CheckStatus({ check, dirty, editable }: { check: Check; dirty: boolean; editable: boolean }) {
  if (!editable || !dirty) return null;
  switch (check.kind) {
    case "checking":
      return <span className="muted">Checking…</span>;
    case "ok":
      return <span className="doc-ok">Valid: {check.outcome === "unchanged" ? "no change" : "ready to save"}</span>;
    case "problems":
      return <span className="status-bad">{check.problems.length === 1 ? "1 problem" : `${check.problems.length} problems`}</span>;
    default:
      return <span className="muted">Unsaved changes</span>;
  }
}
