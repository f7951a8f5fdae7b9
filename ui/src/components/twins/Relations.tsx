import { Link } from "react-router-dom";
import type { RelationNode, RemoteSummary } from "../../api/types";

const STATE_NOTES: Record<string, string> = {
  reachable: "its instance answered the last check",
  stale: "the last check failed; the copy shown may be out of date",
  gone: "its instance says it no longer exists",
  pending: "not fetched yet",
  refused: "this server may not fetch it (TWINLINK_FEDERATION_HOSTS, private addresses)",
};

/** A twin of another instance: linked to its document there, with its name and state. */
function RemoteLink({ id, remote }: { id: string; remote: RemoteSummary }) {
  return (
    <>
      <a href={remote.url} target="_blank" rel="noopener noreferrer" title={id}>
        {remote.name || id}
      </a>{" "}
      <span className="badge">remote</span>{" "}
      <span className={`badge remote-${remote.state}`} title={STATE_NOTES[remote.state] ?? remote.state}>
        {remote.state}
      </span>
      {remote.fetched_at && <span className="muted"> fetched {remote.fetched_at}</span>}
    </>
  );
}

function NodeLink({ node }: { node: RelationNode }) {
  if (node.remote) return <RemoteLink id={node.id} remote={node.remote} />;
  if (node.registered === false || !node.slug) {
    return (
      <span className="mono" title="not registered here">
        {node.id}
      </span>
    );
  }
  return <Link to={`/twins/${encodeURIComponent(node.slug)}`}>{node.name ?? node.slug}</Link>;
}

export function RelationLinks({ title, root }: { title: string; root: RelationNode | undefined }) {
  const nodes = root?.nodes ?? [];
  return (
    <div>
      <h3>{title}</h3>
      {nodes.length === 0 ? (
        <p className="muted">None.</p>
      ) : (
        <ul>
          {nodes.map((node) => (
            <li key={node.id}>
              <NodeLink node={node} />
            </li>
          ))}
        </ul>
      )}
    </div>
  );
}
