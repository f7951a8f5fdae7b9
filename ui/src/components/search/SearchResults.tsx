import { Link } from "react-router-dom";
import type { SearchAnswer } from "../../api/types";
import { Empty } from "../common/Status";
import { featureHref } from "../twins/featureAnchor";
import { Snippet } from "./Snippet";

export function SearchResults({ answer }: { answer: SearchAnswer }) {
  if (answer.hits.length === 0) {
    return <Empty>No twin matches {answer.query ? <q>{answer.query}</q> : "this filter"}.</Empty>;
  }
  return (
    <div>
      <p className="muted">
        {answer.total} {answer.total === 1 ? "twin matches" : "twins match"}
        {answer.total > answer.hits.length && `, the first ${answer.hits.length} shown`}.
      </p>
      <ol className="hits">
        {answer.hits.map((hit) => (
          <li key={hit.slug} className="card">
            <div className="hit-title">
              <Link to={`/twins/${encodeURIComponent(hit.slug)}`}>{hit.name}</Link>
              <span className="muted mono">{hit.slug}</span>
            </div>
            <ul className="matches">
              {hit.matches.map((match, i) => (
                <li key={i}>
                  <span className="match-where">
                    {match.feature ? (
                      <>
                        feature{" "}
                        <Link to={featureHref(hit.slug, match.feature)} className="match-feature">
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
        ))}
      </ol>
    </div>
  );
}
