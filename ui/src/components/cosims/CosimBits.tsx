// Small pieces both Co-simulation pages show: the state as a badge, the progress as a bar.
import type { Cosim } from "../../api/cosims";
import { formatEpochMs } from "../common/time";

export function StateBadge({ state }: { state: string }) {
  return <span className={`badge cosim-state-${state}`}>{state}</span>;
}

export function Progress({ cosim, wide = false }: { cosim: Pick<Cosim, "progress" | "sim_time" | "system">; wide?: boolean }) {
  const fraction = Math.min(1, Math.max(0, cosim.progress ?? 0));
  const percent = Math.round(fraction * 100);
  const end = cosim.system?.end_time;
  return (
    <span className={wide ? "cosim-progress cosim-progress-wide" : "cosim-progress"}>
      <progress max={1} value={fraction} aria-label="Progress" />
      <span>
        {percent}%
        {wide && cosim.sim_time != null && ` (t = ${formatSeconds(cosim.sim_time)}${end != null ? ` of ${formatSeconds(end)}` : ""})`}
      </span>
    </span>
  );
}

const seconds = new Intl.NumberFormat(undefined, { maximumSignificantDigits: 6 });

export function formatSeconds(value: number): string {
  return `${seconds.format(value)} s`;
}

/** A time the API gives as seconds, milliseconds or nanoseconds since the epoch, or ISO text. */
export function formatWhen(value: number | string | null | undefined): string {
  if (value === null || value === undefined || value === "") return "";
  if (typeof value === "string") {
    const ms = Date.parse(value);
    return Number.isNaN(ms) ? value : formatEpochMs(ms);
  }
  if (value > 1e17) return formatEpochMs(value / 1e6);
  if (value > 1e11) return formatEpochMs(value);
  return formatEpochMs(value * 1000);
}
