import { ApiError, apiFetch, apiRequest } from "./client";
import type { Schemas } from "./types";

const enc = encodeURIComponent;
const YAML = "application/yaml";

/** A problem the server found in a DT document, at its line when known. */
export type DocumentProblem = Schemas["ProblemItem"];

export type UpdateAnswer = Schemas["Updated"];

export async function listParts(slug: string, signal?: AbortSignal): Promise<string[]> {
  const answer = await apiFetch<{ levels: string[] }>(`/api/v1/twins/${enc(slug)}/parts`, { signal });
  return answer.levels;
}

/** One privacy part as YAML text, ready to edit. */
export async function getPartYaml(slug: string, level: string, signal?: AbortSignal): Promise<string> {
  const response = await apiRequest(`/api/v1/twins/${enc(slug)}/parts/${enc(level)}`, {
    query: { format: "yaml" },
    accept: YAML,
    signal,
  });
  return response.text();
}

/** PUT one document to the twin; with `dryRun` the server checks it and stores nothing. */
export function putDocument(slug: string, yaml: string, dryRun: boolean, signal?: AbortSignal): Promise<UpdateAnswer> {
  return apiFetch<UpdateAnswer>(`/api/v1/twins/${enc(slug)}`, {
    method: "PUT",
    query: { dry_run: dryRun || undefined },
    body: yaml,
    contentType: YAML,
    signal,
  });
}

/** The document problems of a refused PUT (422/413), or none when the error is of another kind. */
export function documentProblems(error: unknown): DocumentProblem[] {
  if (!(error instanceof ApiError) || !error.problem) return [];
  const errors = error.problem.errors;
  if (!Array.isArray(errors)) return [];
  return errors.filter(
    (e): e is DocumentProblem => typeof e === "object" && e !== null && typeof (e as DocumentProblem).message === "string",
  );
}
