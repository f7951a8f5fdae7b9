// The asset library: browse by kind and scope, search, an asset's versions, upload, download.
// The filters and the open asset live in the URL, so a view can be linked and reloaded.
import { useState } from "react";
import { useSearchParams } from "react-router-dom";
import { KINDS, listAssets, shortDigest, type Asset } from "../api/library";
import { useAuth } from "../auth/AuthContext";
import { Empty, ErrorMessage, Loading } from "../components/common/Status";
import { formatEpochMs } from "../components/common/time";
import { AssetDetails } from "../components/library/AssetDetails";
import { useCart } from "../components/library/cart";
import { ComposePackage } from "../components/library/ComposePackage";
import { UploadForm } from "../components/library/UploadForm";
import { useApi } from "../hooks/useApi";
import { useDebounced } from "../hooks/useDebounced";
import "../components/processors/processors.css";
import "../components/deployments/deployments.css";

/** The scopes a user may name: their own, their groups', and common. */
export function scopesOf(me: { username: string; groups: string[] } | null): string[] {
  if (!me) return ["common"];
  return [`user:${me.username}`, ...me.groups.map((g) => `group:${g}`), "common"];
}

interface TableProps {
  assets: Asset[];
  open: string | null;
  onOpen: (ref: string) => void;
  /** Refs of the assets in the package cart. */
  inCart: (ref: string) => boolean;
  onAdd: (asset: Asset) => void;
}

function AssetTable({ assets, open, onOpen, inCart, onAdd }: TableProps) {
  return (
    <div className="table-scroll">
      <table className="table" aria-label="Assets">
        <thead>
          <tr>
            <th>Asset</th>
            <th>Kind</th>
            <th>Description</th>
            <th>Tags</th>
            <th className="num">Versions</th>
            <th>Changed</th>
            <th>
              <span className="visually-hidden">Actions</span>
            </th>
          </tr>
        </thead>
        <tbody>
          {assets.map((a) => (
            <tr key={a.ref} className={a.ref === open ? "proc-row-open" : undefined}>
              <td>
                <button type="button" className="link-button" aria-expanded={a.ref === open} onClick={() => onOpen(a.ref)}>
                  {a.ref}
                </button>
              </td>
              <td>{a.kind}</td>
              <td>{a.description}</td>
              <td>
                {Object.entries(a.tags).map(([tag, digest]) => (
                  <span key={tag} className="chip" title={digest}>
                    {tag} <span className="muted">{shortDigest(digest).slice(7, 15)}</span>
                  </span>
                ))}
              </td>
              <td className="num">{a.versions}</td>
              <td>{formatEpochMs(a.updated_ns / 1e6)}</td>
              <td className="nowrap">
                {inCart(a.ref) ? (
                  <span className="muted">in the package</span>
                ) : (
                  <button type="button" className="link-button" aria-label={`Add ${a.ref} to the package`} onClick={() => onAdd(a)}>
                    Add to package
                  </button>
                )}
              </td>
            </tr>
          ))}
        </tbody>
      </table>
    </div>
  );
}

function Filters({ kind, scope, scopes, q, set }: {
  kind: string;
  scope: string;
  scopes: string[];
  q: string;
  set: (key: string, value: string) => void;
}) {
  return (
    <>
      <nav className="view-toggle" aria-label="Kinds">
        {["", ...KINDS].map((k) => (
          <button key={k || "all"} type="button" className={k === kind ? "chip chip-on" : "chip"} aria-pressed={k === kind} onClick={() => set("kind", k)}>
            {k || "all kinds"}
          </button>
        ))}
      </nav>
      <div className="search-bar">
        <label htmlFor="lib-q" className="visually-hidden">
          Search the library
        </label>
        <input id="lib-q" type="search" placeholder="Search names, descriptions, keywords…" value={q} onChange={(e) => set("q", e.target.value)} />
        <label htmlFor="lib-scope">Scope</label>
        <select id="lib-scope" value={scope} onChange={(e) => set("scope", e.target.value)}>
          <option value="">all I may read</option>
          {scopes.map((s) => (
            <option key={s} value={s}>
              {s}
            </option>
          ))}
        </select>
      </div>
    </>
  );
}

interface ToolbarProps {
  composing: boolean;
  uploading: boolean;
  /** How many assets the package cart holds. */
  inCart: number;
  onCompose: () => void;
  onUpload: () => void;
}

function Toolbar({ composing, uploading, inCart, onCompose, onUpload }: ToolbarProps) {
  return (
    <>
      <div className="dep-toolbar">
        <h1>Library</h1>
        <span className="spacer" />
        <button type="button" aria-expanded={composing} onClick={onCompose}>
          {composing ? "Close the package" : `Compose a package (${inCart})`}
        </button>
        <button type="button" aria-expanded={uploading} onClick={onUpload}>
          {uploading ? "Close upload" : "Upload"}
        </button>
      </div>
      <p className="muted">
        Data, models, tools, functions and twin packages, in your own space, your groups' and common. Versions are immutable; tags such as latest point at them.
      </p>
    </>
  );
}

/** The filters and the open asset, kept in the page's URL; `set` changes one (typing in the
 * search box replaces the history entry instead of adding one per letter). */
function useLibraryView() {
  const [params, setParams] = useSearchParams();
  const set = (key: string, value: string) =>
    setParams(
      (prev) => {
        const next = new URLSearchParams(prev);
        if (value) next.set(key, value);
        else next.delete(key);
        return next;
      },
      { replace: key === "q" },
    );
  return {
    kind: params.get("kind") ?? "",
    scope: params.get("scope") ?? "",
    q: params.get("q") ?? "",
    open: params.get("asset"),
    set,
  };
}

export function LibraryPage() {
  const { me } = useAuth();
  const [uploading, setUploading] = useState(false);
  const [composing, setComposing] = useState(false);
  const cart = useCart();
  // Counts uploads: the open asset's details are read again after each (a new version).
  const [uploads, setUploads] = useState(0);
  const { kind, scope, q, open, set } = useLibraryView();
  const query = useDebounced(q, 250);
  const assets = useApi((signal) => listAssets({ kind, scope, q: query }, signal), [kind, scope, query]);
  const scopes = scopesOf(me);
  const parts = open?.split("/");
  return (
    <main className="page">
      <Toolbar
        composing={composing}
        uploading={uploading}
        inCart={cart.items.length}
        onCompose={() => setComposing(!composing)}
        onUpload={() => setUploading(!uploading)}
      />
      {uploading && (
        <UploadForm
          scopes={scopes}
          kind={kind}
          onUploaded={(answer) => {
            assets.reload();
            setUploads((n) => n + 1);
            set("asset", answer.asset.ref);
          }}
        />
      )}
      {composing && (
        <ComposePackage
          cart={cart}
          scopes={scopes}
          onPushed={(answer) => {
            assets.reload();
            setUploads((n) => n + 1);
            set("asset", answer.asset.ref);
          }}
        />
      )}
      <Filters kind={kind} scope={scope} scopes={scopes} q={q} set={set} />
      {assets.error && <ErrorMessage error={assets.error} onRetry={assets.reload} />}
      {!assets.data && !assets.error && <Loading />}
      {assets.data && assets.data.length === 0 && <Empty>{q ? `Nothing in the library matches “${q}”.` : "No asset here yet: upload one."}</Empty>}
      {assets.data && assets.data.length > 0 && (
        <AssetTable
          assets={assets.data}
          open={open}
          onOpen={(ref) => set("asset", ref === open ? "" : ref)}
          inCart={(ref) => cart.items.some((i) => i.ref.startsWith(`lib:${ref}@`))}
          onAdd={(asset) => {
            cart.add(asset);
            setComposing(true);
          }}
        />
      )}
      {parts?.length === 3 && (
        <AssetDetails
          key={`${open!}#${uploads}`}
          scope={parts[0]!}
          kind={parts[1]!}
          name={parts[2]!}
          onChanged={assets.reload}
          onDeleted={() => {
            assets.reload();
            set("asset", "");
          }}
        />
      )}
    </main>
  );
}
