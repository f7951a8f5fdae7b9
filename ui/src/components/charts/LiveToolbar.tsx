import type { LiveState } from "../../live/liveClient";
import { windowLabel, WINDOWS_S } from "../../live/selection";

export interface LiveToolbarProps {
  paused: boolean;
  onPause: (paused: boolean) => void;
  windowS: number;
  onWindow: (seconds: number) => void;
  zoomed: boolean;
  onFollow: () => void;
  points: number;
  state: LiveState;
}

/** Pause/Resume, the window length, "Follow live" while zoomed, the count of samples
 * received and the state of the connection. */
export function LiveToolbar({ paused, onPause, windowS, onWindow, zoomed, onFollow, points, state }: LiveToolbarProps) {
  return (
    <div className="toolbar">
      <button type="button" onClick={() => onPause(!paused)}>
        {paused ? "Resume" : "Pause"}
      </button>
      <label>
        Window
        <select value={windowS} onChange={(e) => onWindow(Number(e.target.value))}>
          {WINDOWS_S.map((s) => (
            <option key={s} value={s}>
              {windowLabel(s)}
            </option>
          ))}
        </select>
      </label>
      {zoomed && (
        <button type="button" onClick={onFollow} title="Reset zoom">
          Follow live
        </button>
      )}
      {paused && <span className="paused-note">Paused: not receiving</span>}
      <span className="spacer" />
      <span className="points">
        points received: <span data-testid="live-points">{points}</span>
      </span>
      <StatusBadge state={state} />
    </div>
  );
}

function StatusBadge({ state }: { state: LiveState }) {
  switch (state.kind) {
    case "open":
      return <span className="badge badge-ok">connected</span>;
    case "connecting":
      return <span className="badge">connecting…</span>;
    case "reconnecting":
      return (
        <span className="badge badge-bad" title={state.reason}>
          disconnected: reconnecting in {Math.max(1, Math.round(state.inMs / 1000))} s
        </span>
      );
    default:
      return <span className="badge badge-bad">closed</span>;
  }
}
