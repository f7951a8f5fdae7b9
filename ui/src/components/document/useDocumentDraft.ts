// One part of a twin's document being edited: the loaded text, the edit, its check on the
// server (a dry run once typing pauses) and saving it.
import { useEffect, useState } from "react";
import { documentProblems, getPartYaml, putDocument, type DocumentProblem } from "../../api/documents";
import { useApi } from "../../hooks/useApi";
import { useDebounced } from "../../hooks/useDebounced";

export const CHECK_DEBOUNCE_MS = 600;

export type Check =
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

/** The dry run of a settled edit of the loaded text (`base`), aborted when the text moves on. */
function useDryRun(slug: string, text: string, base: string | undefined, editable: boolean) {
  const [check, setCheck] = useState<Check>({ kind: "idle" });
  const typed = useDebounced(text, CHECK_DEBOUNCE_MS);
  useEffect(() => {
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
  return { check, setCheck };
}

export function useDocumentDraft(slug: string, level: string | undefined, editable: boolean, onSaved: () => void) {
  const part = useApi((signal) => (level ? getPartYaml(slug, level, signal) : Promise.resolve("")), [slug, level]);
  const [text, setText] = useState("");
  // The text the editor was loaded with; undefined until the part has arrived.
  const [base, setBase] = useState<string>();
  const [saved, setSaved] = useState<string>();
  const [saving, setSaving] = useState(false);
  const { check, setCheck } = useDryRun(slug, text, base, editable);

  useEffect(() => {
    if (part.data !== undefined) {
      setText(part.data);
      setBase(part.data);
      setCheck({ kind: "idle" });
    }
  }, [part.data, setCheck]);

  const save = async () => {
    setSaving(true);
    setSaved(undefined);
    try {
      const answer = await putDocument(slug, text, false);
      setSaved(answer.outcome === "unchanged" ? "Nothing to save: the part is unchanged." : "Saved.");
      setCheck({ kind: "idle" });
      part.reload();
      onSaved();
    } catch (error) {
      setCheck(checkOf(error));
    } finally {
      setSaving(false);
    }
  };

  return {
    part,
    text,
    setText,
    dirty: base !== undefined && text !== base,
    revert: () => setText(base ?? ""),
    check,
    saved,
    saving,
    save,
  };
}
