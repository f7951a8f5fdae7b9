import type { ParameterDecl } from "../../api/commands";
import { describeRange, type FieldValue } from "./commandForm";

interface Props {
  param: ParameterDecl;
  value: FieldValue | undefined;
  disabled: boolean;
  onChange: (value: FieldValue) => void;
}

/** One input of a command form, typed by the parameter's declaration. */
export function ParamInput({ param, value, disabled, onChange }: Props) {
  const hint = [param.type, describeRange(param), param.default !== undefined ? `default ${JSON.stringify(param.default)}` : ""]
    .filter(Boolean)
    .join(" · ");
  const label = (
    <span className="param-label">
      <span className="mono">{param.name}</span>
      {param.required && (
        <abbr className="required" title="required">
          *
        </abbr>
      )}
    </span>
  );

  if (param.type === "bool") {
    return (
      <label className="param param-bool" title={param.description}>
        <input type="checkbox" checked={value === true} disabled={disabled} onChange={(e) => onChange(e.target.checked)} />
        {label}
        <span className="param-hint">{hint}</span>
      </label>
    );
  }
  const numeric = param.type === "number" || param.type === "integer";
  return (
    <label className="param" title={param.description}>
      {label}
      <input
        type={numeric ? "number" : "text"}
        inputMode={numeric ? "decimal" : undefined}
        step={param.type === "integer" ? 1 : numeric ? "any" : undefined}
        min={param.min}
        max={param.max}
        required={param.required}
        value={typeof value === "string" ? value : ""}
        disabled={disabled}
        onChange={(e) => onChange(e.target.value)}
      />
      <span className="param-hint">{hint}</span>
    </label>
  );
}
