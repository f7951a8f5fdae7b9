import { useEffect, useState } from "react";
import { Link } from "react-router-dom";
import { listTwins } from "../../api/twins";
import { settle } from "../../hooks/settle";
import type { TwinSummary } from "../../api/types";
import { Empty, ErrorMessage, Loading, formatTime } from "../common/Status";

/** The catalog's empty state, for the list and the tree alike. */
export function NoTwinsYet() {
  return (
    <Empty>
      There are no twins you may see yet. Create one with <code>twinlink apply</code> or ask an owner for a role.
    </Empty>
  );
}

/** The twins the user may see, a page at a time (`next_cursor`). */
export function TwinList() {
  const [items, setItems] = useState<TwinSummary[]>([]);
  const [cursor, setCursor] = useState<string | null>(null);
  const [next, setNext] = useState<string | null>(null);
  const [error, setError] = useState<Error>();
  const [loading, setLoading] = useState(true);

  useEffect(() => {
    const controller = new AbortController();
    setLoading(true);
    settle(listTwins(cursor, 50, controller.signal), controller.signal, {
      value: (page) => {
        setItems((prev) => (cursor === null ? page.items : [...prev, ...page.items]));
        setNext(page.next_cursor);
        setError(undefined);
      },
      error: setError,
      done: () => setLoading(false),
    });
    return () => controller.abort();
  }, [cursor]);

  if (error && items.length === 0) return <ErrorMessage error={error} />;
  if (loading && items.length === 0) return <Loading what="Loading twins" />;
  if (items.length === 0) {
    return <NoTwinsYet />;
  }
  return (
    <div>
      <table className="table">
        <thead>
          <tr>
            <th>Twin</th>
            <th>Slug</th>
            <th>Parts</th>
            <th>Modified</th>
          </tr>
        </thead>
        <tbody>
          {items.map((twin) => (
            <tr key={twin.slug}>
              <td>
                <Link to={`/twins/${encodeURIComponent(twin.slug)}`}>{twin.name}</Link>
              </td>
              <td className="mono">{twin.slug}</td>
              <td>
                {twin.levels.map((level) => (
                  <span key={level} className="badge">
                    {level}
                  </span>
                ))}
              </td>
              <td>{formatTime(twin.modified)}</td>
            </tr>
          ))}
        </tbody>
      </table>
      {error && <ErrorMessage error={error} />}
      {next && (
        <button type="button" disabled={loading} onClick={() => setCursor(next)}>
          {loading ? "Loading…" : "Load more"}
        </button>
      )}
    </div>
  );
}
