import { useRef, useState } from "react";
import { listParts, type DocumentProblem } from "../../api/documents";
import { Empty, ErrorMessage, Loading } from "../../components/common/Status";
import { YamlEditor, type YamlEditorHandle } from "../../components/document/YamlEditor";
import { useDocumentDraft, type Check } from "../../components/document/useDocumentDraft";
import { useApi } from "../../hooks/useApi";
import { canEdit, useTwin } from "./context";

/** The twin's DT document, one privacy part at a time, as YAML: read, check as you type, save. */
export function DocumentTab() {
  const { slug, twin, reload } = useTwin();
  const editable = canEdit(twin);
  const levels = useApi((signal) => listParts(slug, signal), [slug]);
  const [level, setLevel] = useState<string>();
  const chosen = level ?? levels.data?.[levels.data.length - 1];
  const draft = useDocumentDraft(slug, chosen, editable, reload);
  const editor = useRef<YamlEditorHandle>(null);

  if (levels.error) return <ErrorMessage error={levels.error} onRetry={levels.reload} />;
  if (!levels.data) return <Loading what="Loading the document's parts" />;
  if (levels.data.length === 0) return <Empty>You may not see any part of this twin's document.</Empty>;

  const { part, check, dirty, saving } = draft;
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
            <button type="button" disabled={!dirty || saving} onClick={draft.revert}>
              Revert
            </button>
            <button type="submit" disabled={!dirty || saving || check.kind === "problems"} onClick={() => void draft.save()}>
              {saving ? "Saving…" : "Save"}
            </button>
          </>
        )}
      </div>
      {!editable && <p className="muted">Read only: changing the document needs the editor role.</p>}
      {draft.saved && !dirty && <p className="doc-ok" role="status">{draft.saved}</p>}
      {part.error ? (
        <ErrorMessage error={part.error} onRetry={part.reload} />
      ) : part.data === undefined ? (
        <Loading what="Loading the part" />
      ) : (
        <YamlEditor
          ref={editor}
          label={`YAML of the ${chosen} part`}
          value={draft.text}
          onChange={draft.setText}
          problems={check.kind === "problems" ? check.problems : []}
          readOnly={!editable}
        />
      )}
      {check.kind === "error" && <ErrorMessage error={check.error} />}
      {check.kind === "problems" && <ProblemList problems={check.problems} onLine={(line) => editor.current?.goToLine(line)} />}
    </section>
  );
}

/** The problems of the last check, each a button that takes the editor to its line. */
function ProblemList({ problems, onLine }: { problems: DocumentProblem[]; onLine: (line: number) => void }) {
  return (
    <ul className="doc-problems" aria-label="Problems">
      {problems.map((p, i) => (
        <li key={i}>
          <button type="button" onClick={() => p.line && onLine(p.line)}>
            {p.line ? `Line ${p.line}${p.column ? `, column ${p.column}` : ""}: ` : ""}
            {p.path ? `${p.path}: ` : ""}
            {p.message}
          </button>
        </li>
      ))}
    </ul>
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
