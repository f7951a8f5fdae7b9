import { SearchPanel } from "../components/search/SearchPanel";
import { TwinList } from "../components/twins/TwinList";

export function CatalogPage() {
  return (
    <main className="page">
      <h1>Catalog</h1>
      <SearchPanel>
        <TwinList />
      </SearchPanel>
    </main>
  );
}
