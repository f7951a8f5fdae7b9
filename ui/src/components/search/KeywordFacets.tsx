export interface KeywordFacet {
  value: string;
  count: number;
}

/** Keyword chips to filter by; clicking the selected one clears the filter. */
export function KeywordFacets({
  facets,
  selected,
  onSelect,
}: {
  facets: KeywordFacet[];
  selected: string | null;
  onSelect: (keyword: string | null) => void;
}) {
  return (
    <aside className="facets" aria-label="Keywords">
      <h3>Keywords</h3>
      <ul>
        {facets.map((facet) => (
          <li key={facet.value}>
            <button
              type="button"
              className={facet.value === selected ? "chip chip-on" : "chip"}
              aria-pressed={facet.value === selected}
              onClick={() => onSelect(facet.value === selected ? null : facet.value)}
            >
              {facet.value} <span className="muted">{facet.count}</span>
            </button>
          </li>
        ))}
      </ul>
    </aside>
  );
}
