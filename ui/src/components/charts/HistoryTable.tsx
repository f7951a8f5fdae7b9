import type { AggregateAnswer, AggregateFn } from "../../api/history";
import { formatEpochMs } from "../common/time";
import type { SignalSummary } from "./historyData";

const MAX_ROWS = 100;

function time(seconds: number | null): string {
  return seconds === null ? "–" : formatEpochMs(seconds * 1000);
}

function num(value: number | null | undefined): string {
  if (value === null || value === undefined) return "–";
  return Number.isInteger(value) ? String(value) : value.toPrecision(6);
}

/** Per signal of a downsampled range: points drawn, extremes, first and last time. */
export function SummaryTable({ rows }: { rows: SignalSummary[] }) {
  return (
    <table className="table">
      <thead>
        <tr>
          <th>signal</th>
          <th className="num">points drawn</th>
          <th className="num">min</th>
          <th className="num">max</th>
          <th>first</th>
          <th>last</th>
        </tr>
      </thead>
      <tbody>
        {rows.map((r) => (
          <tr key={r.signal}>
            <td className="mono">{r.signal}</td>
            <td className="num">{r.points}</td>
            <td className="num">{num(r.min)}</td>
            <td className="num">{num(r.max)}</td>
            <td>{time(r.first)}</td>
            <td>{time(r.last)}</td>
          </tr>
        ))}
      </tbody>
    </table>
  );
}

/** The first buckets of an aggregate, one row each. */
export function AggregateRows({ answer, signals, fn }: { answer: AggregateAnswer; signals: string[]; fn: AggregateFn }) {
  const rows = answer.rows.slice(0, MAX_ROWS);
  return (
    <div className="rows-table">
      <p className="muted">
        {answer.rows.length.toLocaleString("en-US")} buckets of {answer.bucket}
        {answer.rows.length > MAX_ROWS ? `; the first ${MAX_ROWS} shown` : ""}.
      </p>
      <table className="table">
        <thead>
          <tr>
            <th>bucket start</th>
            {signals.map((s) => (
              <th key={s} className="num">
                {fn}({s})
              </th>
            ))}
          </tr>
        </thead>
        <tbody>
          {rows.map((row) => (
            <tr key={row.time}>
              <td>{time(row.time / 1e9)}</td>
              {signals.map((s) => (
                <td key={s} className="num">
                  {num(row.values[s]?.[fn])}
                </td>
              ))}
            </tr>
          ))}
        </tbody>
      </table>
    </div>
  );
}
