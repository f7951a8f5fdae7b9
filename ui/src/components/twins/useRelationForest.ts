import { useCallback, useEffect, useState } from "react";
import { getRelations, listAllTwins } from "../../api/twins";
import type { RelationNode, TwinSummary } from "../../api/types";
import { settle } from "../../hooks/settle";
import { mapLimited } from "./mapLimited";
import { buildRelationForest, type RelationForest } from "./relationForest";

/** Twins the tree is built for; past that the catalog list (paged) is the way to see them. */
export const MAX_TREE_TWINS = 500;
/** Relation requests in flight at once. */
export const TREE_CONCURRENCY = 4;
/** Levels each twin's subtree is asked for; the subtrees of all twins are merged. */
export const TREE_DEPTH = 3;

export interface LoadedForest {
  forest: RelationForest;
  twinCount: number;
  /** Whether every twin the user may see was loaded (at most MAX_TREE_TWINS are). */
  complete: boolean;
  /** Twins whose relations could not be loaded, and the first reason. */
  failed: number;
  firstFailure?: Error;
}

export type Progress = { done: number; total: number } | null;

function asError(reason: unknown): Error {
  return reason instanceof Error ? reason : new Error(String(reason));
}

/** Load the twins, then their subtrees a few at a time, and build the forest. It fails only
 * when no twin's relations could be loaded; otherwise the failures are counted. */
export async function loadRelationForest(
  signal: AbortSignal,
  onProgress: (progress: Progress) => void,
): Promise<LoadedForest> {
  const { items, complete } = await listAllTwins(MAX_TREE_TWINS, signal);
  onProgress({ done: 0, total: items.length });
  const subtreeOf = (twin: TwinSummary) => getRelations(twin.slug, "down", signal, TREE_DEPTH);
  const outcomes = await mapLimited(items, TREE_CONCURRENCY, subtreeOf, {
    signal,
    onSettled: (done) => onProgress({ done, total: items.length }),
  });
  const subtrees: RelationNode[] = [];
  const failures: Error[] = [];
  for (const outcome of outcomes) {
    if (outcome.status === "fulfilled") subtrees.push(outcome.value);
    else failures.push(asError(outcome.reason));
  }
  if (items.length > 0 && subtrees.length === 0) throw failures[0] ?? new Error("No relations could be loaded.");
  return {
    forest: buildRelationForest(items, subtrees),
    twinCount: items.length,
    complete,
    failed: failures.length,
    firstFailure: failures[0],
  };
}

export interface RelationForestState {
  data?: LoadedForest;
  error?: Error;
  progress: Progress;
  reload: () => void;
}

export function useRelationForest(): RelationForestState {
  const [data, setData] = useState<LoadedForest>();
  const [error, setError] = useState<Error>();
  const [progress, setProgress] = useState<Progress>(null);
  const [tick, setTick] = useState(0);
  const reload = useCallback(() => setTick((t) => t + 1), []);

  useEffect(() => {
    const controller = new AbortController();
    setData(undefined);
    setError(undefined);
    setProgress(null);
    const report = (p: Progress) => {
      if (!controller.signal.aborted) setProgress(p);
    };
    settle(loadRelationForest(controller.signal, report), controller.signal, {
      value: setData,
      error: setError,
      done: () => setProgress(null),
    });
    return () => controller.abort();
  }, [tick]);

  return { data, error, progress, reload };
}
