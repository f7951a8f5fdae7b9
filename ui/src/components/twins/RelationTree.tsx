import { useState } from "react";
import { Link } from "react-router-dom";
import { ErrorMessage, Loading } from "../common/Status";
import type { RelationTreeNode } from "./relationForest";
import { NoTwinsYet } from "./TwinList";
import { MAX_TREE_TWINS, useRelationForest, type LoadedForest } from "./useRelationForest";

/** Levels open when the tree first shows; deeper nodes open on a click. */
const OPEN_LEVELS = 2;

function NodeLabel({ node }: { node: RelationTreeNode }) {
  const name = node.slug ? (
    <Link to={`/twins/${encodeURIComponent(node.slug)}`}>{node.name}</Link>
  ) : (
    <span className="mono" title="Not a twin registered here">
      {node.id}
    </span>
  );
  return (
    <>
      {name}
      <span className="badge">{node.relation === "root" ? "top level" : "child"}</span>
      {!node.slug && <span className="badge">not registered</span>}
      {node.cycle && (
        <span className="badge" title="This twin is already an ancestor on this branch">
          cycle
        </span>
      )}
    </>
  );
}

function TreeItem({ node, level }: { node: RelationTreeNode; level: number }) {
  const [open, setOpen] = useState(level < OPEN_LEVELS);
  const hasChildren = node.children.length > 0;
  return (
    <li>
      <div className="tree-row">
        {hasChildren ? (
          <button
            type="button"
            className="link-button tree-toggle"
            aria-expanded={open}
            aria-label={`${open ? "Collapse" : "Expand"} ${node.name}`}
            onClick={() => setOpen(!open)}
          >
            {open ? "▾" : "▸"}
          </button>
        ) : (
          <span className="tree-toggle" aria-hidden="true" />
        )}
        <NodeLabel node={node} />
        {hasChildren && !open && <span className="muted">{node.children.length} below</span>}
      </div>
      {hasChildren && open && <TreeLevel nodes={node.children} level={level + 1} />}
    </li>
  );
}

function TreeLevel({ nodes, level, label }: { nodes: RelationTreeNode[]; level: number; label?: string }) {
  return (
    <ul className={level === 0 ? "tree tree-root" : "tree"} aria-label={label}>
      {nodes.map((node) => (
        <TreeItem key={node.key} node={node} level={level} />
      ))}
    </ul>
  );
}

function TreeNotes({ data }: { data: LoadedForest }) {
  return (
    <>
      {!data.forest.hasRelations && (
        <p className="muted">None of these twins has a child twin yet, so the tree is flat.</p>
      )}
      {!data.complete && (
        <p className="notice">The tree shows the first {MAX_TREE_TWINS} twins; the list view pages through all.</p>
      )}
      {data.forest.truncated && <p className="notice">The tree is too large to show whole; it was cut short.</p>}
      {data.failed > 0 && (
        <p className="notice">
          The relations of {data.failed} {data.failed === 1 ? "twin" : "twins"} could not be loaded
          {data.firstFailure ? ` (${data.firstFailure.message})` : ""}; they show without children.
        </p>
      )}
    </>
  );
}

/** The twins the user may see, as a tree of parent → child relations. */
export function RelationTree() {
  const { data, error, progress, reload } = useRelationForest();
  if (error) return <ErrorMessage error={error} onRetry={reload} />;
  if (!data) {
    const what = progress ? `Loading relations (${progress.done} of ${progress.total} twins)` : "Loading twins";
    return <Loading what={what} />;
  }
  if (data.twinCount === 0) {
    return <NoTwinsYet />;
  }
  return (
    <div>
      <TreeNotes data={data} />
      <TreeLevel nodes={data.forest.roots} level={0} label="Relation tree" />
    </div>
  );
}
