import { useEffect, useState, type ReactNode } from "react";
import { catalogKeywords, search } from "../../api/search";
import type { SearchAnswer } from "../../api/types";
import { settle } from "../../hooks/settle";
import { useApi } from "../../hooks/useApi";
import { useDebounced } from "../../hooks/useDebounced";
import { ErrorMessage, Loading } from "../common/Status";
import { KeywordFacets } from "./KeywordFacets";
import { SearchResults } from "./SearchResults";

export const SEARCH_DEBOUNCE_MS = 200;

/** Search as you type; while the box and keyword are empty, `children` (the catalog) shows,
 * beside the keywords of the whole catalog to filter by. */
export function SearchPanel({ children }: { children?: ReactNode }) {
  const [text, setText] = useState("");
  const [keyword, setKeyword] = useState<string | null>(null);
  const q = useDebounced(text.trim(), SEARCH_DEBOUNCE_MS);
  const [answer, setAnswer] = useState<SearchAnswer>();
  const [error, setError] = useState<Error>();
  const active = q !== "" || keyword !== null;
  // Loaded once: the catalog's keywords, shown before anything is typed.
  const catalog = useApi((signal) => catalogKeywords(signal), []);

  useEffect(() => {
    if (!active) {
      setAnswer(undefined);
      setError(undefined);
      return;
    }
    const controller = new AbortController();
    settle(search(q, keyword, controller.signal), controller.signal, {
      value: (value) => {
        setAnswer(value);
        setError(undefined);
      },
      error: setError,
      done: () => {},
    });
    return () => controller.abort();
  }, [q, keyword, active]);

  const catalogFacets = catalog.data ?? [];
  // Until the first answer of a search arrives, the catalog's keywords stay in place.
  const facets = active ? (answer?.facets?.keywords ?? catalogFacets) : catalogFacets;

  let main: ReactNode = children;
  if (active) {
    if (error) main = <ErrorMessage error={error} />;
    else if (answer) main = <SearchResults answer={answer} />;
    else main = <Loading what="Searching" />;
  }

  return (
    <section>
      <div className="search-bar">
        <input
          type="search"
          aria-label="Search twins and features"
          placeholder="Search twins and features, e.g. crane history"
          value={text}
          onChange={(e) => setText(e.target.value)}
          autoFocus
        />
        {keyword && (
          <button type="button" className="chip chip-on" onClick={() => setKeyword(null)} title="Remove this filter">
            keyword: {keyword} ×
          </button>
        )}
      </div>
      <div className="search-layout">
        <div className="search-main">{main}</div>
        {facets.length > 0 && <KeywordFacets facets={facets} selected={keyword} onSelect={setKeyword} />}
      </div>
    </section>
  );
}
