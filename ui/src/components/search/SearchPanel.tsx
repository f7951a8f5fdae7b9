import { useEffect, useState, type ReactNode } from "react";
import { search } from "../../api/search";
import type { SearchAnswer } from "../../api/types";
import { settle } from "../../hooks/settle";
import { useDebounced } from "../../hooks/useDebounced";
import { ErrorMessage, Loading } from "../common/Status";
import { SearchResults } from "./SearchResults";

export const SEARCH_DEBOUNCE_MS = 200;

/** Search as you type; while the box and keyword are empty, `children` (the catalog) shows. */
export function SearchPanel({ children }: { children?: ReactNode }) {
  const [text, setText] = useState("");
  const [keyword, setKeyword] = useState<string | null>(null);
  const q = useDebounced(text.trim(), SEARCH_DEBOUNCE_MS);
  const [answer, setAnswer] = useState<SearchAnswer>();
  const [error, setError] = useState<Error>();
  const [loading, setLoading] = useState(false);
  const active = q !== "" || keyword !== null;

  useEffect(() => {
    if (!active) {
      setAnswer(undefined);
      setError(undefined);
      return;
    }
    const controller = new AbortController();
    setLoading(true);
    settle(search(q, keyword, controller.signal), controller.signal, {
      value: (value) => {
        setAnswer(value);
        setError(undefined);
      },
      error: setError,
      done: () => setLoading(false),
    });
    return () => controller.abort();
  }, [q, keyword, active]);

  const facets = answer?.facets?.keywords ?? [];

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
      {active ? (
        <div className="search-layout">
          <div className="search-main">
            {error ? <ErrorMessage error={error} /> : answer ? <SearchResults answer={answer} /> : loading && <Loading what="Searching" />}
          </div>
          {facets.length > 0 && (
            <aside className="facets" aria-label="Keywords">
              <h3>Keywords</h3>
              <ul>
                {facets.map((facet) => (
                  <li key={facet.value}>
                    <button
                      type="button"
                      className={facet.value === keyword ? "chip chip-on" : "chip"}
                      onClick={() => setKeyword(facet.value === keyword ? null : facet.value)}
                    >
                      {facet.value} <span className="muted">{facet.count}</span>
                    </button>
                  </li>
                ))}
              </ul>
            </aside>
          )}
        </div>
      ) : (
        children
      )}
    </section>
  );
}
