// Reconfigure a deployment: new parameters (the form generated from its package's schema,
// filled with the values it runs with) and/or another version of its package; the diff plan
// first, then applied. Resources that do not change are left running.
import { useEffect, useMemo, useState, type FormEvent } from "react";
import { changeDeployment, type ChangeRequest, type Deployment, type Plan } from "../../api/deployments";
import { ErrorMessage, Loading } from "../common/Status";
import { SchemaForm } from "../processors/schema/SchemaForm";
import { schemaPaths } from "../processors/schema/schema";
import { NO_ERRORS, type FormErrors } from "../processors/serverErrors";
import { deployErrors } from "./NewDeployment";
import { checkParameters } from "./packageParams";
import { parsePinned, usePackageInfo, VersionPicker } from "./PackagePicker";
import { PlanView } from "./PlanView";

interface Props {
  deployment: Deployment;
  onDone: () => void;
  onCancel: () => void;
}

export function Reconfigure({ deployment, onDone, onCancel }: Props) {
  const pinned = parsePinned(deployment.package);
  const asset = pinned ? `${pinned.scope}/${pinned.kind}/${pinned.name}` : "";
  const [version, setVersion] = useState(pinned?.version ?? "");
  const [parameters, setParameters] = useState<Record<string, unknown>>(deployment.parameters);
  const [plan, setPlan] = useState<Plan | null>(null);
  const [errors, setErrors] = useState<FormErrors>(NO_ERRORS);
  const [busy, setBusy] = useState(false);
  const [valid, setValid] = useState(true);
  const info = usePackageInfo({ asset, version });
  const schema = info.data?.parameters ?? null;
  const known = useMemo(() => new Set(["parameters", "package", ...(schema ? schemaPaths(schema, schema, "parameters") : [])]), [schema]);
  useEffect(() => {
    setPlan(null);
    setErrors(NO_ERRORS);
  }, [version, parameters]);

  const change = (): ChangeRequest => ({
    parameters,
    ...(version !== pinned?.version ? { package: `${asset}@${version}` } : {}),
  });
  async function submit(event: FormEvent) {
    event.preventDefault();
    const found = checkParameters(schema, parameters);
    if (Object.keys(found).length) {
      setErrors({ fields: found, general: null, error: new Error("check the marked fields") });
      return;
    }
    setBusy(true);
    setErrors(NO_ERRORS);
    try {
      if (!plan) setPlan((await changeDeployment(deployment.name, change(), true)).plan);
      else {
        await changeDeployment(deployment.name, change(), false);
        onDone();
      }
    } catch (err) {
      setErrors(deployErrors(err, known));
    } finally {
      setBusy(false);
    }
  }

  if (!pinned) return <ErrorMessage error={new Error(`The deployment's package ${deployment.package} is not a library reference.`)} />;
  return (
    <form className="card proc-form" aria-label="Reconfigure" onSubmit={(e) => void submit(e)} noValidate>
      <h3>Reconfigure</h3>
      {errors.general && <ErrorMessage error={new Error(errors.general)} />}
      {errors.error && !errors.general && <div className="error">Nothing was changed: see the fields marked below.</div>}
      <fieldset disabled={busy} className="proc-bare">
        <div className="proc-basics">
          <VersionPicker id="reconf-version" asset={{ scope: pinned.scope, kind: pinned.kind, name: pinned.name, ref: asset, tags: {} }} value={version} onChange={setVersion} />
        </div>
        {info.error && <ErrorMessage error={info.error} onRetry={info.reload} />}
        {!info.data && !info.error && <Loading what="Reading the package's twin.yaml" />}
        {info.data &&
          (schema ? (
            <SchemaForm schema={schema} value={parameters} onChange={setParameters} path="parameters" errors={errors.fields} onValidity={setValid} />
          ) : (
            <p className="muted">This package takes no parameters.</p>
          ))}
      </fieldset>
      {plan && <PlanView plan={plan} />}
      <div className="proc-buttons">
        <button type="submit" disabled={busy || !info.data || !valid}>
          {plan ? (busy ? "Applying…" : "Apply") : busy ? "Planning…" : "Plan changes"}
        </button>
        <button type="button" onClick={onCancel}>
          Cancel
        </button>
      </div>
    </form>
  );
}
