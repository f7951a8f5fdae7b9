// Create a processor: pick a blueprint, fill the form made from its parameter schema (or, for
// an FMU, the variable-mapping view), name it and choose its streams.
import { useCallback, useMemo, useState, type FormEvent } from "react";
import { createProcessor, getBlueprint, listBlueprints, listStreams, type Processor } from "../../api/processors";
import { useApi } from "../../hooks/useApi";
import { ErrorMessage, Loading } from "../common/Status";
import { buildSpec, freeName, type CreateDraft } from "./buildSpec";
import { BasicsFields, BlueprintPicker, LimitsFields } from "./CreateFields";
import { BlueprintParams } from "./BlueprintParams";
import { schemaPaths } from "./schema/schema";
import { formErrors, NO_ERRORS, type FormErrors } from "./serverErrors";

const SPEC_PATHS = [
  "name", "blueprint", "source", "output", "inputs", "params", "enabled", "rates", "memory_limit_mb", "batch_timeout_s",
  "rates.min_input_spacing_s", "rates.min_step_spacing_s", "rates.min_output_spacing_s", "rates.max_batch",
];

interface Props {
  slug: string;
  existing: Processor[];
  /** Changes when FMUs were uploaded, so the FMU choice is loaded again. */
  fmusVersion: number;
  onCreated: (processor: Processor) => void;
  onCancel: () => void;
}

function emptyDraft(): CreateDraft {
  return { name: "", blueprint: "", source: "telemetry", output: "", enabled: true, inputs: [], params: {}, limits: { rates: {} }, fmu: null };
}

/** The streams a processor may read: stored ones, other processors' outputs, and telemetry. */
function streamChoices(stored: string[], existing: Processor[]): string[] {
  const names = new Set(["telemetry", ...stored, ...existing.map((p) => p.output || p.name)]);
  return [...names];
}

/** What the form loads: blueprints, the chosen one's schema, the twin's streams and signals. */
function useCreateData(slug: string, draft: CreateDraft, existing: Processor[]) {
  const blueprints = useApi((signal) => listBlueprints(signal), []);
  const streams = useApi((signal) => listStreams(slug, signal), [slug]);
  const detail = useApi((signal) => (draft.blueprint ? getBlueprint(draft.blueprint, signal) : Promise.resolve(null)), [draft.blueprint]);
  const schema = detail.data?.params_schema;
  const known = useMemo(() => new Set([...SPEC_PATHS, ...(schema ? schemaPaths(schema, schema, "params") : [])]), [schema]);
  const streamNames = streamChoices((streams.data ?? []).map((s) => s.name), existing);
  const signals = useMemo(
    () => (streams.data ?? []).find((s) => s.name === draft.source)?.signals?.map((s) => s.name) ?? [],
    [streams.data, draft.source],
  );
  return { blueprints, streams, detail, schema, known, streamNames, signals };
}

/** Sending the draft: what must be fixed first, or the server's answer placed at the fields. */
function useSubmit(slug: string, draft: CreateDraft, known: ReadonlySet<string>, onCreated: (p: Processor) => void) {
  const [errors, setErrors] = useState<FormErrors>(NO_ERRORS);
  const [saving, setSaving] = useState(false);
  async function submit(event: FormEvent) {
    event.preventDefault();
    const { spec, problems } = buildSpec(draft);
    if (Object.keys(problems).length) {
      setErrors({ fields: problems, general: null, error: new Error("check the marked fields") });
      return;
    }
    setSaving(true);
    setErrors(NO_ERRORS);
    try {
      onCreated(await createProcessor(slug, spec));
    } catch (err) {
      setErrors(formErrors(err, known));
    } finally {
      setSaving(false);
    }
  }
  return { errors, setErrors, saving, submit };
}

export function CreateProcessor({ slug, existing, fmusVersion, onCreated, onCancel }: Props) {
  const [draft, setDraft] = useState<CreateDraft>(emptyDraft);
  const [nameEdited, setNameEdited] = useState(false);
  const [valid, setValid] = useState(true);
  const { blueprints, streams, detail, schema, known, streamNames, signals } = useCreateData(slug, draft, existing);
  const { errors, setErrors, saving, submit } = useSubmit(slug, draft, known, onCreated);
  const change = useCallback((part: Partial<CreateDraft>) => setDraft((d) => ({ ...d, ...part })), []);

  function chooseBlueprint(name: string) {
    const taken = existing.map((p) => p.name);
    change({ blueprint: name, params: {}, inputs: [], fmu: null, ...(nameEdited || !name ? {} : { name: freeName(name, taken) }) });
    setErrors(NO_ERRORS);
  }

  if (blueprints.error) return <ErrorMessage error={blueprints.error} onRetry={blueprints.reload} />;
  if (!blueprints.data) return <Loading what="Loading the blueprints" />;
  const fields = errors.fields;
  return (
    <form className="card proc-form" aria-label="New processor" onSubmit={(e) => void submit(e)} noValidate>
      <h3>New processor</h3>
      {errors.general && <ErrorMessage error={new Error(errors.general)} />}
      {errors.error && !errors.general && <div className="error">The processor was not created: see the fields marked below.</div>}
      <fieldset disabled={saving} className="proc-bare">
        <BlueprintPicker blueprints={blueprints.data} value={draft.blueprint} onChange={chooseBlueprint} error={fields.blueprint} />
        {draft.blueprint && (
          <>
            <BasicsFields
              draft={draft}
              streams={streamNames}
              errors={fields}
              onChange={(part) => {
                if (part.name !== undefined) setNameEdited(true);
                change(part);
              }}
            />
            {streams.error && <p className="muted">The stream list could not be loaded ({streams.error.message}); type signal names instead.</p>}
            {detail.error && <ErrorMessage error={detail.error} onRetry={detail.reload} />}
            {schema && <BlueprintParams slug={slug} draft={draft} schema={schema} onChange={change} signals={signals} errors={fields} fmusVersion={fmusVersion} onValidity={setValid} />}
            <LimitsFields limits={draft.limits} onChange={(limits) => change({ limits })} errors={fields} />
          </>
        )}
      </fieldset>
      <div className="proc-buttons">
        <button type="submit" disabled={saving || !draft.blueprint || !valid}>
          {saving ? "Creating…" : "Create processor"}
        </button>
        <button type="button" onClick={onCancel}>
          Cancel
        </button>
        {!valid && <span className="sf-error">Fix the fields marked as not valid first.</span>}
      </div>
    </form>
  );
}
