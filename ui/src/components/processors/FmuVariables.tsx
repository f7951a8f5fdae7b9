import type { FmuVariable } from "../../api/processors";

const ORDER = ["input", "output", "parameter", "calculatedParameter", "structuralParameter", "local", "independent"];

function show(value: unknown): string {
  return value === null || value === undefined ? "" : String(value);
}

/** An FMU's variables: inputs first, then outputs and parameters. */
export function FmuVariables({ variables, caption }: { variables: FmuVariable[]; caption?: string }) {
  const rank = (v: FmuVariable) => {
    const i = ORDER.indexOf(v.causality);
    return i < 0 ? ORDER.length : i;
  };
  const sorted = [...variables].sort((a, b) => rank(a) - rank(b));
  return (
    <table className="table proc-vars" aria-label={caption ?? "FMU variables"}>
      <thead>
        <tr>
          <th>Name</th>
          <th>Causality</th>
          <th>Variability</th>
          <th>Type</th>
          <th>Unit</th>
          <th className="num">Start</th>
          <th className="num">Min</th>
          <th className="num">Max</th>
          <th>Description</th>
        </tr>
      </thead>
      <tbody>
        {sorted.map((v) => (
          <tr key={v.name}>
            <td className="mono">{v.name}</td>
            <td>{v.causality}</td>
            <td>{v.variability}</td>
            <td>{v.type}</td>
            <td>{show(v.unit)}</td>
            <td className="num">{show(v.start)}</td>
            <td className="num">{show(v.min)}</td>
            <td className="num">{show(v.max)}</td>
            <td className="muted">{show(v.description)}</td>
          </tr>
        ))}
      </tbody>
    </table>
  );
}
