import type { ProcessorState } from "../../api/processors";

const TONES: Record<string, string> = {
  running: "badge-ok",
  starting: "proc-badge-busy",
  stopping: "proc-badge-busy",
  backoff: "badge-bad",
  failed: "badge-bad",
  crashed: "badge-bad",
};

/** A processor's state as a coloured badge: green running, amber changing, red broken. */
export function StateBadge({ state }: { state: ProcessorState }) {
  return <span className={`badge proc-state ${TONES[state] ?? ""}`.trim()}>{state}</span>;
}
