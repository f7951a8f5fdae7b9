import { Link, NavLink, Outlet, useParams } from "react-router-dom";
import { getTwin } from "../../api/twins";
import { ErrorMessage, Loading } from "../../components/common/Status";
import { useApi } from "../../hooks/useApi";
import type { TwinContext } from "./context";

const TABS: [string, string][] = [
  ["", "Overview"],
  ["live", "Live"],
  ["history", "History"],
  ["commands", "Commands"],
  ["processors", "Processors"],
  ["document", "Document"],
];

/** A twin: its name and the tabs; each tab is a nested route that gets the twin as context. */
export function TwinPage() {
  const slug = useParams().slug ?? "";
  const twin = useApi((signal) => getTwin(slug, signal), [slug]);

  if (twin.error) {
    return (
      <main className="page">
        <p>
          <Link to="/">← Catalog</Link>
        </p>
        <ErrorMessage error={twin.error} onRetry={twin.reload} />
      </main>
    );
  }
  if (!twin.data) return <main className="page"><Loading what="Loading the twin" /></main>;

  const context: TwinContext = { slug, twin: twin.data, reload: twin.reload };
  return (
    <main className="page">
      <p>
        <Link to="/">← Catalog</Link>
      </p>
      <h1>{twin.data.document.name ?? twin.data.name}</h1>
      <nav className="tabs" aria-label="Twin sections">
        {TABS.map(([path, label]) => (
          <NavLink key={label} to={path ? `/twins/${encodeURIComponent(slug)}/${path}` : `/twins/${encodeURIComponent(slug)}`} end>
            {label}
          </NavLink>
        ))}
      </nav>
      <Outlet context={context} />
    </main>
  );
}
