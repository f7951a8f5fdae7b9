// Compose a twin package from the assets in the cart: their aliases, the package's name and
// scope, and its twin.yaml (written from the cart, editable), pushed as a `twins` asset whose
// one file is twin.yaml. It is then deployed like any package.
import { useEffect, useId, useState, type FormEvent } from "react";
import { Link } from "react-router-dom";
import { pushVersion, type PushAnswer } from "../../api/library";
import { ErrorMessage } from "../common/Status";
import { PlainField } from "../processors/CreateFields";
import { ALIAS, twinYamlFor, type useCart } from "./cart";
import { NAME } from "./UploadForm";

interface Props {
  cart: ReturnType<typeof useCart>;
  scopes: string[];
  onPushed: (answer: PushAnswer) => void;
}

function CartList({ cart }: { cart: Props["cart"] }) {
  if (!cart.items.length) return <p className="muted">The cart is empty: choose “Add to package” on the assets the twin uses.</p>;
  return (
    <table className="table" aria-label="Assets of the package">
      <thead>
        <tr>
          <th>Name in the package</th>
          <th>Asset</th>
          <th>
            <span className="visually-hidden">Actions</span>
          </th>
        </tr>
      </thead>
      <tbody>
        {cart.items.map((item, i) => (
          <tr key={item.ref}>
            <td>
              <input
                aria-label={`Name of ${item.ref} in the package`}
                value={item.alias}
                aria-invalid={!ALIAS.test(item.alias)}
                onChange={(e) => cart.rename(i, e.target.value)}
              />
            </td>
            <td className="mono">{item.ref}</td>
            <td>
              <button type="button" className="link-button" aria-label={`Remove ${item.ref} from the package`} onClick={() => cart.remove(i)}>
                Remove
              </button>
            </td>
          </tr>
        ))}
      </tbody>
    </table>
  );
}

export function ComposePackage({ cart, scopes, onPushed }: Props) {
  const id = useId();
  const [name, setName] = useState("");
  const [scope, setScope] = useState(scopes[0] ?? "common");
  const [description, setDescription] = useState("");
  const [yaml, setYaml] = useState(() => twinYamlFor(cart.items, ""));
  const [edited, setEdited] = useState(false);
  const [error, setError] = useState<Error | null>(null);
  const [done, setDone] = useState<PushAnswer | null>(null);
  const [busy, setBusy] = useState(false);
  // Written again from the cart as it changes, until it is edited by hand.
  useEffect(() => {
    if (!edited) setYaml(twinYamlFor(cart.items, description));
  }, [cart.items, description, edited]);

  async function submit(event: FormEvent) {
    event.preventDefault();
    const bad = cart.items.find((i) => !ALIAS.test(i.alias));
    if (!NAME.test(name)) return setError(new Error("Name the package: lower case letters, digits, '.', '_' and '-', starting with a letter or digit."));
    if (bad) return setError(new Error(`"${bad.alias}" cannot name an asset in a package: letters, digits, _ and -, starting with a letter or _.`));
    setBusy(true);
    setError(null);
    try {
      const file = new File([yaml], "twin.yaml", { type: "application/yaml" });
      const answer = await pushVersion({ scope, kind: "twins", name, file, format: "file", tags: ["latest"] });
      setDone(answer);
      onPushed(answer);
    } catch (err) {
      setError(err instanceof Error ? err : new Error(String(err)));
    } finally {
      setBusy(false);
    }
  }

  return (
    <form className="card proc-form" aria-label="Compose a package" onSubmit={(e) => void submit(e)} noValidate>
      <h3>Compose a twin package</h3>
      {error && <ErrorMessage error={error} />}
      {done && (
        <p className="proc-result" role="status">
          Pushed {done.asset.ref}: <Link to="/deployments">deploy it</Link> from the Deployments page.
        </p>
      )}
      <CartList cart={cart} />
      <fieldset className="proc-bare" disabled={busy}>
        <div className="proc-basics">
          <PlainField id={`${id}-name`} label="Package name" path="name" required hint="Lower case: letters, digits, '.', '_', '-'.">
            <input id={`${id}-name`} value={name} required onChange={(e) => setName(e.target.value)} />
          </PlainField>
          <PlainField id={`${id}-scope`} label="Scope" path="scope" required>
            <select id={`${id}-scope`} value={scope} onChange={(e) => setScope(e.target.value)}>
              {scopes.map((s) => (
                <option key={s} value={s}>
                  {s}
                </option>
              ))}
            </select>
          </PlainField>
          <PlainField id={`${id}-description`} label="Description" path="description">
            <input id={`${id}-description`} value={description} onChange={(e) => setDescription(e.target.value)} />
          </PlainField>
        </div>
        <PlainField id={`${id}-yaml`} label="twin.yaml" path="yaml" hint={edited ? "Edited by hand: the cart no longer writes it." : "Written from the cart; edit it to add parameters, devices, processors…"}>
          <textarea
            id={`${id}-yaml`}
            className="mono"
            rows={Math.min(24, yaml.split("\n").length + 1)}
            value={yaml}
            spellCheck={false}
            onChange={(e) => {
              setEdited(true);
              setYaml(e.target.value);
            }}
          />
        </PlainField>
      </fieldset>
      <div className="proc-buttons">
        <button type="submit" disabled={busy}>
          {busy ? "Pushing…" : "Push package"}
        </button>
        {edited && (
          <button type="button" onClick={() => setEdited(false)}>
            Write it from the cart again
          </button>
        )}
        <button type="button" onClick={cart.clear} disabled={!cart.items.length}>
          Empty the cart
        </button>
      </div>
    </form>
  );
}
