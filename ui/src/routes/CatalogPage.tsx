import { useSearchParams } from "react-router-dom";
import { SearchPanel } from "../components/search/SearchPanel";
import { RelationTree } from "../components/twins/RelationTree";
import { TwinList } from "../components/twins/TwinList";

type CatalogView = "list" | "tree";

const VIEWS: [CatalogView, string][] = [
  ["list", "List"],
  ["tree", "Tree"],
];

/** The list or the relation tree, kept in the URL (`?view=tree`) so a link or reload keeps it. */
function useCatalogView(): [CatalogView, (view: CatalogView) => void] {
  const [params, setParams] = useSearchParams();
  const view: CatalogView = params.get("view") === "tree" ? "tree" : "list";
  const setView = (next: CatalogView) => {
    setParams((prev) => {
      const updated = new URLSearchParams(prev);
      if (next === "list") updated.delete("view");
      else updated.set("view", next);
      return updated;
    });
  };
  return [view, setView];
}

export function CatalogPage() {
  const [view, setView] = useCatalogView();
  return (
    <main className="page">
      <h1>Catalog</h1>
      <SearchPanel>
        <div className="view-toggle" role="group" aria-label="Catalog view">
          {VIEWS.map(([value, label]) => (
            <button
              key={value}
              type="button"
              className={value === view ? "chip chip-on" : "chip"}
              aria-pressed={value === view}
              onClick={() => setView(value)}
            >
              {label}
            </button>
          ))}
        </div>
        {view === "tree" ? <RelationTree /> : <TwinList />}
      </SearchPanel>
    </main>
  );
}
