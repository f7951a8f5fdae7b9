import { apiFetch } from "./client";
import type { SearchAnswer } from "./types";

export function search(
  q: string,
  keyword: string | null,
  signal?: AbortSignal,
): Promise<SearchAnswer> {
  return apiFetch<SearchAnswer>("/api/v1/search", { query: { q, keyword, limit: 50 }, signal });
}
