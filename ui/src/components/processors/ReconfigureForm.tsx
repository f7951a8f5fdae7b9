// Change a processor's parameters with the form of its blueprint's schema (PATCH {params}).
import { useMemo, useState, type FormEvent } from "react";
import { getBlueprint, updateProcessor, type Processor } from "../../api/processors";
import { useApi } from "../../hooks/useApi";
import { ErrorMessage, Loading } from "../common/Status";
import { schemaPaths } from "./schema/schema";
import { SchemaForm } from "./schema/SchemaForm";
import { formErrors, NO_ERRORS, type FormErrors } from "./serverErrors";

interface Props {
  slug: string;
  processor: Processor;
  onSaved: () => void;
  onClose: () => void;
}

export function ReconfigureForm({ slug, processor, onSaved, onClose }: Props) {
  const blueprint = useApi((signal) => getBlueprint(processor.blueprint, signal), [processor.blueprint]);
  // The form starts from the parameters as they were when it opened; polling does not reset it.
  const [params, setParams] = useState<Record<string, unknown>>(() => ({ ...processor.params }));
  const [valid, setValid] = useState(true);
  const [saving, setSaving] = useState(false);
  const [errors, setErrors] = useState<FormErrors>(NO_ERRORS);
  const [result, setResult] = useState<string | null>(null);
  const schema = blueprint.data?.params_schema;
  const known = useMemo(() => new Set(schema ? schemaPaths(schema, schema, "params") : ["params"]), [schema]);

  async function save(event: FormEvent) {
    event.preventDefault();
    setSaving(true);
    setErrors(NO_ERRORS);
    setResult(null);
    try {
      const answer = await updateProcessor(slug, processor.name, { params });
      setResult(`Parameters saved: ${answer.kept_state ? "state kept" : "restarted"} (${answer.state}).`);
      onSaved();
    } catch (err) {
      setErrors(formErrors(err, known));
    } finally {
      setSaving(false);
    }
  }

  if (blueprint.error) return <ErrorMessage error={blueprint.error} onRetry={blueprint.reload} />;
  if (!schema) return <Loading what="Loading the blueprint's parameters" />;
  const placed = errors.error && !errors.general;
  return (
    <form className="proc-form card" aria-label={`Parameters of ${processor.name}`} onSubmit={(e) => void save(e)}>
      <h4>Change the parameters of {processor.name}</h4>
      <p className="muted">
        {blueprint.data?.keeps_state
          ? "This blueprint can take new parameters while it runs and keep its state."
          : "The worker restarts with the new parameters."}
      </p>
      {errors.general && <ErrorMessage error={new Error(errors.general)} />}
      {placed && <div className="error">The parameters were not saved: see the fields marked below.</div>}
      <fieldset disabled={saving} className="proc-bare">
        <SchemaForm schema={schema} value={params} onChange={setParams} path="params" errors={errors.fields} onValidity={setValid} />
      </fieldset>
      <div className="proc-buttons">
        <button type="submit" disabled={saving || !valid}>
          {saving ? "Saving…" : "Save parameters"}
        </button>
        <button type="button" onClick={onClose}>
          Close
        </button>
      </div>
      {result && (
        <div className="proc-result" role="status">
          {result}
        </div>
      )}
    </form>
  );
}
