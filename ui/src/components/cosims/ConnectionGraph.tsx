// A co-simulation's connection graph as SVG: instances as boxes in layers, arrows labelled
// with the variables they carry, the arrows that close a cycle drawn below the boxes from right
// to left, and the instances and connections of an algebraic loop in red. The same facts
// follow as a list, for those who do not see the drawing.
import { useMemo } from "react";
import type { CosimSystem } from "../../api/cosims";
import { layoutGraph, splitPort } from "./graphLayout";

const KIND_NOTE: Record<string, string> = { "model-exchange": "ME", python: "Python" };

export function ConnectionGraph({ system }: { system: CosimSystem }) {
  const names = useMemo(() => system.instances.map((i) => i.name), [system]);
  const layout = useMemo(
    () => layoutGraph({ instances: names, connections: system.connections, loops: system.loops ?? [] }),
    [names, system],
  );
  const kinds = new Map(system.instances.map((i) => [i.name, i]));
  const loops = (system.loops ?? []).map((loop) => loop.map((p) => {
    const port = splitPort(p, names);
    return `${port.instance}.${port.variable}`;
  }));
  return (
    <figure className="cosim-graph">
      <div className="cosim-graph-scroll">
        <svg
          role="img"
          aria-label={`Connection graph: ${layout.boxes.length} instances, ${system.connections.length} connections`}
          width={layout.width}
          height={layout.height}
          viewBox={`0 0 ${layout.width} ${layout.height}`}
        >
          <defs>
            <marker id="cosim-arrow" viewBox="0 0 10 10" refX="9" refY="5" markerWidth="8" markerHeight="8" markerUnits="userSpaceOnUse" orient="auto-start-reverse">
              <path d="M 0 0 L 10 5 L 0 10 z" className="cosim-arrowhead" />
            </marker>
            <marker id="cosim-arrow-loop" viewBox="0 0 10 10" refX="9" refY="5" markerWidth="8" markerHeight="8" markerUnits="userSpaceOnUse" orient="auto-start-reverse">
              <path d="M 0 0 L 10 5 L 0 10 z" className="cosim-arrowhead cosim-loop" />
            </marker>
          </defs>
          {layout.edges.map((e) => (
            <g key={`${e.from}>${e.to}`} className={`cosim-edge cosim-edge-${e.kind}${e.inLoop ? " cosim-loop" : ""}`} data-from={e.from} data-to={e.to}>
              <title>{`${e.from} → ${e.to}: ${e.labels.join(", ")}${e.inLoop ? " (algebraic loop)" : ""}`}</title>
              <path d={e.path} fill="none" markerEnd={`url(#${e.inLoop ? "cosim-arrow-loop" : "cosim-arrow"})`} />
              <rect x={e.labelX - e.labelWidth / 2} y={e.labelY - 9} width={e.labelWidth} height={16} rx={3} className="cosim-label-bg" />
              <text x={e.labelX} y={e.labelY + 3} textAnchor="middle" className="cosim-label">
                {e.text}
              </text>
            </g>
          ))}
          {layout.boxes.map((b) => {
            const kind = KIND_NOTE[kinds.get(b.name)?.kind ?? ""];
            const isolated = kinds.get(b.name)?.isolated;
            return (
              <g key={b.name} className={`cosim-box${b.inLoop ? " cosim-loop" : ""}`} data-instance={b.name}>
                <title>{`${b.name}: ${kinds.get(b.name)?.fmu ?? "not listed"}${isolated ? " (own process)" : ""}`}</title>
                <rect x={b.x} y={b.y} width={b.width} height={b.height} rx={5} />
                <text x={b.x + b.width / 2} y={b.y + b.height / 2 + 4} textAnchor="middle">
                  {b.name}
                </text>
                {(kind || isolated) && (
                  <text x={b.x + b.width - 4} y={b.y + 10} textAnchor="end" className="cosim-box-note">
                    {[kind, isolated ? "isolated" : ""].filter(Boolean).join(" ")}
                  </text>
                )}
              </g>
            );
          })}
        </svg>
      </div>
      <figcaption>
        {loops.length > 0 ? (
          <div className="cosim-loops" role="note">
            <strong>{loops.length === 1 ? "An algebraic loop" : `${loops.length} algebraic loops`}</strong> (in red): the masters do not iterate, so a
            start is refused until the loop is broken (a variable that does not feed through, or a delay).
            <ul className="plain-list">
              {loops.map((loop) => (
                <li key={loop.join(" ")} className="mono">
                  {[...loop, loop[0]].join(" → ")}
                </li>
              ))}
            </ul>
          </div>
        ) : (
          <span className="muted">No algebraic loop.</span>
        )}
        <details>
          <summary>Connections as a list</summary>
          <ul className="plain-list mono" aria-label="Connections">
            {system.connections.map((c, i) => {
              const s = splitPort(c.source, names);
              const t = splitPort(c.target, names);
              return <li key={i}>{`${s.instance}.${s.variable} → ${t.instance}.${t.variable}`}</li>;
            })}
          </ul>
        </details>
      </figcaption>
    </figure>
  );
}
