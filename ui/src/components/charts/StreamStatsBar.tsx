import type { Percentiles, StreamStatsSnapshot } from "../../live/delayStats";

function ms(value: number): string {
  const size = Math.abs(value);
  return size >= 10 ? `${Math.round(value)} ms` : `${value.toFixed(1)} ms`;
}

function delayText(label: string, p: Percentiles | null): string {
  return p ? `${label} ${ms(p.median)} (p99 ${ms(p.p99)})` : `${label} –`;
}

export function rateText(perSecond: number): string {
  return `${Math.round(perSecond).toLocaleString("en-US")} samples/s`;
}

/** Per stream: the live delay (sent − sample time), the time in the platform (sent −
 * received), the rate received and what the server dropped, over the last seconds. */
export function StreamStatsBar({ stats }: { stats: Map<string, StreamStatsSnapshot> }) {
  return (
    <div className="stream-stats" aria-label="Live delay per stream">
      {[...stats].map(([stream, s]) => (
        <span key={stream} data-testid={`stats-${stream}`}>
          <span className="stream-name">{stream}</span>: {delayText("delay", s.delay)} · {delayText("platform", s.platform)} ·{" "}
          {rateText(s.samplesPerSecond)}
          {s.droppedSamples > 0 && (
            <span className="dropped">
              {" "}
              · dropped {s.droppedSamples.toLocaleString("en-US")} samples ({s.droppedMessages} messages): this browser reads too slowly
            </span>
          )}
        </span>
      ))}
    </div>
  );
}
