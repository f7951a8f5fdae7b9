import type { Processor } from "../../api/processors";
import { formatCount } from "./format";
import { StateBadge } from "./StateBadge";

interface Props {
  processors: Processor[];
  selected: string | null;
  onSelect: (name: string | null) => void;
}

/** The twin's processors, one row each; a name opens the processor's details. */
export function ProcessorTable({ processors, selected, onSelect }: Props) {
  return (
    <table className="table proc-table" aria-label="Processors">
      <thead>
        <tr>
          <th>Name</th>
          <th>Blueprint</th>
          <th>Stream</th>
          <th>State</th>
          <th className="num">In</th>
          <th className="num">Out</th>
          <th className="num">Restarts</th>
          <th>Last error</th>
        </tr>
      </thead>
      <tbody>
        {processors.map((p) => (
          <tr key={p.name} className={p.name === selected ? "proc-row proc-row-open" : "proc-row"} data-testid={`processor-${p.name}`}>
            <td>
              <button
                type="button"
                className="link-button mono"
                aria-expanded={p.name === selected}
                aria-label={`Details of ${p.name}`}
                onClick={() => onSelect(p.name === selected ? null : p.name)}
              >
                {p.name}
              </button>
            </td>
            <td className="mono">{p.blueprint}</td>
            <td className="mono">
              {p.source} → {p.output || p.name}
            </td>
            <td>
              <StateBadge state={p.state} />
              {!p.enabled && p.state !== "stopped" && <span className="muted"> (stopping)</span>}
            </td>
            <td className="num">{formatCount(p.stats?.samples_in)}</td>
            <td className="num">{formatCount(p.stats?.samples_out)}</td>
            <td className="num">{formatCount(p.stats?.restarts)}</td>
            <td className="proc-error-cell" title={p.last_error ?? undefined}>
              {p.last_error ?? <span className="muted">none</span>}
            </td>
          </tr>
        ))}
      </tbody>
    </table>
  );
}
