import { Link } from "react-router-dom";
import type { SearchAnswer } from "../../api/types";
import { Empty } from "../common/Status";
import { featureHref } from "../twins/featureAnchor";
import { Snippet } from "./Snippet";

// A hit is a twin, or a library asset (kind "asset": no slug, its ref instead), which the
// server lists after the twins.
type Hit = SearchAnswer["hits"][number];

function AssetHit({ hit }: { hit: Hit }) {
  return (
    <li className="card">
      <div className="hit-title">
        <Link to={`/library?asset=${encodeURIComponent(hit.ref ?? "")}`}>{hit.name}</Link>
        <span className="muted mono">{hit.ref}</span>
        <span className="badge">{hit.asset_kind}</span>
      </div>
      {hit.description && <p className="matches">{hit.description}</p>}
    </li>
  );
}

function TwinHit({ hit, slug }: { hit: Hit; slug: string }) {
  return (
    <li className="card">
      <div className="hit-title">
        <Link to={`/twins/${encodeURIComponent(slug)}`}>{hit.name}</Link>
        <span className="muted mono">{slug}</span>
      </div>
      <ul className="matches">
        {hit.matches.map((match, i) => (
          <li key={i}>
            <span className="match-where">
              {match.feature ? (
                <>
                  feature{" "}
                  <Link to={featureHref(slug, match.feature)} className="match-feature">
                    {match.feature}
                  </Link>
                </>
              ) : (
                "twin"
              )}
              <span className="badge">{match.privacy}</span>
            </span>
            <Snippet snippet={match.snippet} />
          </li>
        ))}
      </ul>
    </li>
  );
}

export function SearchResults({ answer }: { answer: SearchAnswer }) {
  if (answer.hits.length === 0) {
    return <Empty>No twin or library asset matches {answer.query ? <q>{answer.query}</q> : "this filter"}.</Empty>;
  }
  const hits = answer.hits as Hit[];
  return (
    <div>
      <p className="muted">
        {answer.total} {answer.total === 1 ? "match" : "matches"}
        {answer.total > answer.hits.length && `, the first ${answer.hits.length} shown`}.
      </p>
      <ol className="hits">
        {hits.map((hit) =>
          hit.kind === "asset" ? <AssetHit key={`asset:${hit.ref}`} hit={hit} /> : <TwinHit key={hit.slug} hit={hit} slug={hit.slug ?? ""} />,
        )}
      </ol>
    </div>
  );
}
