import { readInterface, type ParameterDecl, type ValueDecl } from "../../api/commands";
import type { TwinDocument } from "../../api/types";
import { WordBreaks } from "../common/WordBreaks";

const numbers = new Intl.NumberFormat(undefined, { maximumSignificantDigits: 8 });

/** "0 – 1", "≥ 1", "≤ 100" or nothing. */
export function rangeText(decl: Pick<ValueDecl, "min" | "max">): string {
  const { min, max } = decl;
  if (min !== undefined && max !== undefined) return `${numbers.format(min)} – ${numbers.format(max)}`;
  if (min !== undefined) return `≥ ${numbers.format(min)}`;
  if (max !== undefined) return `≤ ${numbers.format(max)}`;
  return "";
}

function ValueTable<T extends ValueDecl>({ caption, decls, extra }: { caption: string; decls: T[]; extra?: [string, (d: T) => string] }) {
  return (
    <table className="table interface-table">
      <caption>{caption}</caption>
      <thead>
        <tr>
          <th>Name</th>
          <th>Type</th>
          <th>Unit</th>
          <th>Range</th>
          {extra && <th>{extra[0]}</th>}
          <th>Description</th>
        </tr>
      </thead>
      <tbody>
        {decls.map((d) => (
          <tr key={d.name}>
            <td className="mono">
              <WordBreaks text={d.name} />
            </td>
            <td>{d.type}</td>
            <td>{d.unit ?? ""}</td>
            <td className="nowrap">{rangeText(d)}</td>
            {extra && <td>{extra[1](d)}</td>}
            <td>{d.description ?? ""}</td>
          </tr>
        ))}
      </tbody>
    </table>
  );
}

function parameterText(p: ParameterDecl): string {
  const parts = [p.type, p.unit, rangeText(p), p.required ? "required" : "optional"];
  if (p.default !== undefined) parts.push(`default ${JSON.stringify(p.default)}`);
  return parts.filter(Boolean).join(", ");
}

/** A twin's machine-readable `interface` as tables: the signals it sends, the properties it
 * reports, the commands it takes with their parameters. */
export function InterfaceTables({ document }: { document: TwinDocument }) {
  const { signals, properties, commands, defaultDevice } = readInterface(document);
  if (signals.length + properties.length + commands.length === 0 && !defaultDevice) return null;
  return (
    <div className="interface table-scroll">
      {signals.length > 0 && <ValueTable caption="Signals" decls={signals} />}
      {properties.length > 0 && (
        <ValueTable caption="Properties" decls={properties} extra={["Writable", (d) => (d.writable ? "yes" : "no")]} />
      )}
      {commands.length > 0 && (
        <table className="table interface-table">
          <caption>Commands</caption>
          <thead>
            <tr>
              <th>Name</th>
              <th>Parameters</th>
              <th>Description</th>
            </tr>
          </thead>
          <tbody>
            {commands.map((c) => (
              <tr key={c.name}>
                <td className="mono">
                  <WordBreaks text={c.name} />
                </td>
                <td>
                  {c.parameters.length === 0 ? (
                    <span className="muted">none</span>
                  ) : (
                    <ul className="plain-list">
                      {c.parameters.map((p) => (
                        <li key={p.name}>
                          <span className="mono">{p.name}</span> <span className="muted">({parameterText(p)})</span>
                          {p.description && <div>{p.description}</div>}
                        </li>
                      ))}
                    </ul>
                  )}
                </td>
                <td>{c.description ?? ""}</td>
              </tr>
            ))}
          </tbody>
        </table>
      )}
      {defaultDevice && (
        <p>
          Commands go to the device <span className="mono">{defaultDevice}</span> unless another one is chosen.
        </p>
      )}
    </div>
  );
}
