import { Link } from "react-router-dom";
import type { RelationNode } from "../../api/types";

function NodeLink({ node }: { node: RelationNode }) {
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
