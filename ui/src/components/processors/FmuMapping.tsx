// The `fmu` blueprint's own view: choose an uploaded FMU, then feed each FMU input from a
// measured signal (scaled and offset), choose the outputs and set parameters.
import { useEffect } from "react";
import { getFmu, type Fmu } from "../../api/processors";
import { useApi } from "../../hooks/useApi";
import { ErrorMessage, Loading } from "../common/Status";
import { initialFmuChoice, type FmuChoice } from "./buildSpec";
import { FmuInputsTable, FmuOutputsChoice, FmuParametersTable } from "./FmuMappingParts";

interface Props {
  slug: string;
  fmus: Fmu[];
  choice: FmuChoice | null;
  onChange: (choice: FmuChoice | null) => void;
  /** The source stream's signals. */
  signals: string[];
  errors: Record<string, string>;
}

export function FmuMapping({ slug, fmus, choice, onChange, signals, errors }: Props) {
  const name = choice?.fmu ?? "";
  const detail = useApi((signal) => (name ? getFmu(slug, name, signal) : Promise.resolve(null)), [slug, name]);
  const loaded = detail.data;

  useEffect(() => {
    // A newly chosen FMU gets its mapping once its variables are known.
    if (choice && !choice.variables && loaded && loaded.name === choice.fmu) {
      onChange(initialFmuChoice(choice.fmu, loaded.variables ?? [], signals));
    }
  }, [choice, loaded, signals, onChange]);

  function choose(fmu: string) {
    onChange(fmu ? { fmu, variables: null, feeds: {}, outputs: [], parameters: {} } : null);
  }

  return (
    <div className="proc-fmu">
      <div className="sf-field" data-path="params.fmu">
        <div className="sf-label">
          <label htmlFor="proc-fmu-choice">FMU</label>
          <code className="sf-key">fmu</code>
          <span className="sf-required">required</span>
        </div>
        <select id="proc-fmu-choice" value={name} required onChange={(e) => choose(e.target.value)}>
          <option value="">Choose…</option>
          {fmus.map((f) => (
            <option key={f.name} value={f.name}>
              {f.name}
              {f.model_name ? ` (${f.model_name})` : ""}
            </option>
          ))}
        </select>
        <div className="sf-hint">
          {fmus.length ? "An FMU uploaded to this twin (see FMUs below)." : "No FMU has been uploaded to this twin yet: upload one under FMUs below."}
        </div>
        {errors["params.fmu"] && <div className="sf-error">{errors["params.fmu"]}</div>}
      </div>
      {detail.error && <ErrorMessage error={detail.error} onRetry={detail.reload} />}
      {choice && !choice.variables && !detail.error && <Loading what="Loading the FMU's variables" />}
      {choice?.variables && (
        <>
          <FmuInputsTable choice={choice} onChange={onChange} signals={signals} error={errors["inputs"] ?? errors["params.inputs"]} />
          <FmuOutputsChoice choice={choice} onChange={onChange} error={errors["params.outputs"]} />
          <FmuParametersTable choice={choice} onChange={onChange} error={errors["params.parameters"]} />
        </>
      )}
    </div>
  );
}
