// "New deployment": a twin package and its version, a name, the form generated from the
// package's parameter schema, then the plan (nothing is stored), then "Deploy".
import { useEffect, useMemo, useState, type FormEvent } from "react";
import { createDeployment, planDeployment, type CreateAnswer, type DeploymentRequest, type Plan } from "../../api/deployments";
import type { Asset } from "../../api/library";
import { ErrorMessage, Loading } from "../common/Status";
import { PlainField } from "../processors/CreateFields";
import { SchemaForm } from "../processors/schema/SchemaForm";
import { schemaPaths } from "../processors/schema/schema";
import { ApiError } from "../../api/client";
import { formErrors, NO_ERRORS, type FormErrors } from "../processors/serverErrors";
import { checkParameters, parameterDefaults } from "./packageParams";
import { PackagePicker, packageRef, usePackageInfo, type PackageChoice } from "./PackagePicker";
import { PlanView } from "./PlanView";

const NAME_HINT = "The twin's slug: lower case letters, digits and dashes.";

/** A free slug-like name from an asset name ("tingen-rig" -> "tingen-rig"). */
export function nameFor(asset: string): string {
  return asset.toLowerCase().replace(/[^a-z0-9]+/g, "-").replace(/^-+|-+$/g, "");
}

// The deployments API names a parameter that does not fit as "parameter zeta: 3 is greater than
// the maximum of 2" (nested ones dotted): placed at that field of the form.
const PARAMETER = /^parameter ([\w-]+(?:\.[\w-]+)*): (.+)$/s;

/** A refusal's messages at the fields they name; the rest above the form. */
export function deployErrors(error: unknown, known: ReadonlySet<string>): FormErrors {
  if (error instanceof ApiError && error.status === 422) {
    const match = PARAMETER.exec(error.detail);
    if (match && known.has(`parameters.${match[1]}`)) {
      return { fields: { [`parameters.${match[1]}`]: match[2]! }, general: null, error };
    }
  }
  return formErrors(error, known);
}

interface Props {
  onCreated: (answer: CreateAnswer) => void;
  onCancel: () => void;
}

function useDeployForm() {
  const [choice, setChoice] = useState<PackageChoice>({ asset: "", version: "" });
  const [name, setName] = useState("");
  const [parameters, setParameters] = useState<Record<string, unknown>>({});
  const [start, setStart] = useState(true);
  const [plan, setPlan] = useState<Plan | null>(null);
  const [errors, setErrors] = useState<FormErrors>(NO_ERRORS);
  const [busy, setBusy] = useState<"plan" | "deploy" | null>(null);
  const info = usePackageInfo(choice);
  const schema = info.data?.parameters ?? null;
  // A newly read package starts from its defaults; values typed for another one are dropped.
  useEffect(() => setParameters(parameterDefaults(schema)), [schema]);
  // Any change makes the plan shown stale (it must be asked for again), and the messages
  // about what was sent.
  useEffect(() => {
    setPlan(null);
    setErrors(NO_ERRORS);
  }, [choice, name, parameters]);
  const known = useMemo(() => new Set(["name", "package", "parameters", ...(schema ? schemaPaths(schema, schema, "parameters") : [])]), [schema]);
  const request = (): DeploymentRequest => ({ package: packageRef(choice), name, parameters });
  function problems(): boolean {
    const found = checkParameters(schema, parameters);
    if (!name) found.name = "give the deployment a name";
    if (!Object.keys(found).length) return false;
    setErrors({ fields: found, general: null, error: new Error("check the marked fields") });
    return true;
  }
  async function run(kind: "plan" | "deploy", fn: () => Promise<void>) {
    if (problems()) return;
    setBusy(kind);
    setErrors(NO_ERRORS);
    try {
      await fn();
    } catch (err) {
      setErrors(deployErrors(err, known));
    } finally {
      setBusy(null);
    }
  }
  return { choice, setChoice, name, setName, parameters, setParameters, start, setStart, plan, setPlan, errors, busy, info, schema, request, run };
}

export function NewDeployment({ onCreated, onCancel }: Props) {
  const form = useDeployForm();
  const [nameEdited, setNameEdited] = useState(false);
  const [valid, setValid] = useState(true);
  const fields = form.errors.fields;

  function choosePackage(choice: PackageChoice, asset: Asset | null) {
    form.setChoice(choice);
    if (!nameEdited) form.setName(asset ? nameFor(asset.name) : "");
  }
  function submit(event: FormEvent) {
    event.preventDefault();
    if (!form.plan) void form.run("plan", async () => form.setPlan(await planDeployment(form.request())));
    else void form.run("deploy", async () => onCreated(await createDeployment({ ...form.request(), start: form.start })));
  }

  return (
    <form className="card proc-form" aria-label="New deployment" onSubmit={submit} noValidate>
      <h3>New deployment</h3>
      {form.errors.general && <ErrorMessage error={new Error(form.errors.general)} />}
      {form.errors.error && !form.errors.general && <div className="error">Nothing was deployed: see the fields marked below.</div>}
      <fieldset disabled={form.busy !== null} className="proc-bare">
        <PackagePicker value={form.choice} onChange={choosePackage} error={fields.package} />
        <PlainField id="dep-name" label="Name" path="name" required hint={NAME_HINT} error={fields.name}>
          <input
            id="dep-name"
            value={form.name}
            required
            onChange={(e) => {
              setNameEdited(true);
              form.setName(e.target.value);
            }}
          />
        </PlainField>
        {form.info.error && <ErrorMessage error={form.info.error} onRetry={form.info.reload} />}
        {form.choice.version && !form.info.data && !form.info.error && <Loading what="Reading the package's twin.yaml" />}
        {form.info.data && (
          <section aria-label="Parameters">
            <h4>Parameters</h4>
            {form.info.data.description && <p className="muted">{form.info.data.description}</p>}
            {form.schema ? (
              <SchemaForm schema={form.schema} value={form.parameters} onChange={form.setParameters} path="parameters" errors={fields} onValidity={setValid} />
            ) : (
              <p className="muted">This package takes no parameters.</p>
            )}
          </section>
        )}
        <label className="sf-check">
          <input type="checkbox" checked={form.start} onChange={(e) => form.setStart(e.target.checked)} /> Start it once it is created
        </label>
      </fieldset>
      {form.plan && <PlanView plan={form.plan} />}
      <div className="proc-buttons">
        <button type="submit" disabled={form.busy !== null || !form.info.data || !valid}>
          {form.plan ? (form.busy === "deploy" ? "Deploying…" : "Deploy") : form.busy === "plan" ? "Planning…" : "Plan"}
        </button>
        {form.plan && (
          <button type="button" onClick={() => form.setPlan(null)}>
            Change
          </button>
        )}
        <button type="button" onClick={onCancel}>
          Cancel
        </button>
        {!valid && <span className="sf-error">Fix the fields marked as not valid first.</span>}
      </div>
    </form>
  );
}
