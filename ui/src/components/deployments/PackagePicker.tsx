// Choosing a twin package and one of its versions (a tag, or a version by its digest), and
// reading the chosen version's twin.yaml.
import { getAsset, listAssets, readVersionFile, shortDigest, type Asset } from "../../api/library";
import { useApi } from "../../hooks/useApi";
import { PlainField } from "../processors/CreateFields";
import { parseTwinYaml, type PackageInfo } from "./packageParams";

export interface PackageChoice {
  /** "<scope>/twins/<name>" of the library, or "" before one is chosen. */
  asset: string;
  /** A tag or a digest of that asset. */
  version: string;
}

export function splitRef(ref: string): { scope: string; kind: string; name: string } | null {
  const parts = ref.split("/");
  return parts.length === 3 ? { scope: parts[0]!, kind: parts[1]!, name: parts[2]! } : null;
}

/** The package as the deployment API takes it: "<scope>/twins/<name>@<tag or digest>". */
export function packageRef(choice: PackageChoice): string {
  return `${choice.asset}@${choice.version || "latest"}`;
}

/** "lib:<scope>/<kind>/<name>@<ref>[#path]" (a deployment's pinned package) in its parts. */
export function parsePinned(ref: string): { scope: string; kind: string; name: string; version: string } | null {
  const match = /^lib:([^/]+)\/([^/]+)\/([^@#/]+)@([^#]+)/.exec(ref);
  return match ? { scope: match[1]!, kind: match[2]!, name: match[3]!, version: match[4]! } : null;
}

/** The chosen version's twin.yaml, read: what the form is generated from. */
export function usePackageInfo(choice: PackageChoice) {
  return useApi(async (signal): Promise<PackageInfo | null> => {
    const ref = splitRef(choice.asset);
    if (!ref || !choice.version) return null;
    const text = await readVersionFile(ref.scope, ref.kind, ref.name, choice.version, "twin.yaml", signal);
    return parseTwinYaml(text);
  }, [choice.asset, choice.version]);
}

type AssetRef = Pick<Asset, "scope" | "kind" | "name" | "ref" | "tags">;

/** A tag or a version of `asset`, by its digest. */
export function VersionPicker({ asset, value, onChange, id = "dep-version" }: { asset: AssetRef; value: string; onChange: (v: string) => void; id?: string }) {
  const details = useApi((signal) => getAsset(asset.scope, asset.kind, asset.name, signal), [asset.ref]);
  const tags = Object.entries(details.data?.tags ?? asset.tags).sort(([a], [b]) => (a === "latest" ? -1 : b === "latest" ? 1 : a.localeCompare(b)));
  return (
    <PlainField id={id} label="Version" path="version" required hint="A tag, or one version by its digest." error={details.error?.message}>
      <select id={id} value={value} required onChange={(e) => onChange(e.target.value)}>
        {!tags.length && !details.data && <option value="">Loading…</option>}
        <optgroup label="Tags">
          {tags.map(([tag, digest]) => (
            <option key={tag} value={tag}>
              {tag} ({shortDigest(digest)})
            </option>
          ))}
        </optgroup>
        {details.data && details.data.versions.length > 0 && (
          <optgroup label="Versions">
            {details.data.versions.map((v) => (
              <option key={v.digest} value={v.digest}>
                {shortDigest(v.digest)}
                {v.tags.length ? ` (${v.tags.join(", ")})` : ""}
              </option>
            ))}
          </optgroup>
        )}
      </select>
    </PlainField>
  );
}

interface Props {
  value: PackageChoice;
  onChange: (choice: PackageChoice, asset: Asset | null) => void;
  error?: string;
}

export function PackagePicker({ value, onChange, error }: Props) {
  const packages = useApi((signal) => listAssets({ kind: "twins" }, signal), []);
  const assets = packages.data ?? [];
  const chosen = assets.find((a) => a.ref === value.asset) ?? null;
  function choose(ref: string) {
    const asset = assets.find((a) => a.ref === ref) ?? null;
    const version = asset ? (asset.tags.latest ? "latest" : (Object.keys(asset.tags)[0] ?? asset.latest ?? "")) : "";
    onChange({ asset: ref, version }, asset);
  }
  const hint = packages.data && !assets.length ? "There is no twin package in the library you may read: upload one on the Library page (kind twins)." : undefined;
  return (
    <div className="proc-basics">
      <PlainField id="dep-package" label="Twin package" path="package" required hint={hint} error={error ?? packages.error?.message}>
        <select id="dep-package" value={value.asset} required onChange={(e) => choose(e.target.value)}>
          <option value="">{packages.data ? "Choose a package…" : "Loading…"}</option>
          {assets.map((a) => (
            <option key={a.ref} value={a.ref}>
              {a.ref}
              {a.description ? `: ${a.description}` : ""}
            </option>
          ))}
        </select>
      </PlainField>
      {chosen && <VersionPicker asset={chosen} value={value.version} onChange={(version) => onChange({ ...value, version }, chosen)} />}
    </div>
  );
}
