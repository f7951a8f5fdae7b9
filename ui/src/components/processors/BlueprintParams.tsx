// The blueprint's part of the create form: the form generated from its parameter schema and
// an input mapping, or for the `fmu` blueprint the FMU mapping view.
import { useEffect } from "react";
import { listFmus, type JsonSchema } from "../../api/processors";
import { useApi } from "../../hooks/useApi";
import { ErrorMessage, Loading } from "../common/Status";
import type { CreateDraft, FmuChoice } from "./buildSpec";
import { FmuMapping } from "./FmuMapping";
import { InputMappingEditor } from "./InputMappingEditor";
import { SchemaForm } from "./schema/SchemaForm";

/** The FMU blueprint's parameters that the mapping view edits itself. */
const FMU_OWN = ["fmu", "inputs", "outputs", "parameters"];

interface Props {
  slug: string;
  draft: CreateDraft;
  schema: JsonSchema;
  onChange: (change: Partial<CreateDraft>) => void;
  signals: string[];
  errors: Record<string, string>;
  fmusVersion: number;
  onValidity: (valid: boolean) => void;
}

export function BlueprintParams(props: Props) {
  const { draft, schema, onChange, signals, errors, onValidity } = props;
  if (draft.blueprint === "fmu") return <FmuParams {...props} />;
  return (
    <>
      <fieldset className="sf-group">
        <legend>Parameters of {draft.blueprint}</legend>
        <SchemaForm schema={schema} value={draft.params} onChange={(params) => onChange({ params })} path="params" errors={errors} suggestions={signals} onValidity={onValidity} />
      </fieldset>
      <InputMappingEditor rows={draft.inputs} onChange={(inputs) => onChange({ inputs })} signals={signals} error={errors.inputs} />
    </>
  );
}

function FmuParams({ slug, draft, schema, onChange, signals, errors, fmusVersion, onValidity }: Props) {
  const fmus = useApi((signal) => listFmus(slug, signal), [slug, fmusVersion]);
  const only = fmus.data?.length === 1 ? fmus.data[0]!.name : null;
  useEffect(() => {
    // With a single FMU uploaded there is nothing to choose.
    if (only && !draft.fmu) onChange({ fmu: { fmu: only, variables: null, feeds: {}, outputs: [], parameters: {} } });
  }, [only, draft.fmu, onChange]);

  const setChoice = (fmu: FmuChoice | null) => {
    if (fmu?.fmu === draft.fmu?.fmu && fmu && !fmu.variables && draft.fmu?.variables) return; // chosen again
    onChange({ fmu });
  };
  const advancedError = Object.keys(errors).some((k) => k.startsWith("params.") && !FMU_OWN.includes(k.slice("params.".length)));
  if (fmus.error) return <ErrorMessage error={fmus.error} onRetry={fmus.reload} />;
  if (!fmus.data) return <Loading what="Loading the twin's FMUs" />;
  return (
    <>
      <FmuMapping slug={slug} fmus={fmus.data} choice={draft.fmu} onChange={setChoice} signals={signals} errors={errors} />
      <details className="proc-details" open={advancedError}>
        <summary>More FMU settings (stepping, solver, ranges, logging)</summary>
        <SchemaForm schema={schema} value={draft.params} onChange={(params) => onChange({ params })} path="params" errors={errors} omit={FMU_OWN} onValidity={onValidity} />
      </details>
    </>
  );
}
