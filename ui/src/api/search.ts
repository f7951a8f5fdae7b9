import { apiFetch } from "./client";
import type { SearchAnswer } from "./types";

export function search(
  q: string,
  keyword: string | null,
  signal?: AbortSignal,
  limit = 50,
): Promise<SearchAnswer> {
  return apiFetch<SearchAnswer>("/api/v1/search", { query: { q, keyword, limit }, signal });
}

/** The keyword facets of the whole catalog: an empty query matches every twin, and the
 * facets are counted over the first hits whatever the limit, so one hit is enough. */
export async function catalogKeywords(signal?: AbortSignal): Promise<{ value: string; count: number }[]> {
  const answer = await search("", null, signal, 1);
  return answer.facets?.keywords ?? [];
}
