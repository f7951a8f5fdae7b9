// A small typed fetch wrapper for the twinlink API.
//
// The token is kept in sessionStorage, not localStorage: it dies with the browser tab, so a
// forgotten tab on a shared machine does not leave a usable token behind on disk for later
// visitors, and every new tab signs in afresh.

const TOKEN_KEY = "twinlink.token";

export function getToken(): string | null {
  return sessionStorage.getItem(TOKEN_KEY);
}

export function setToken(token: string): void {
  sessionStorage.setItem(TOKEN_KEY, token);
}

export function clearToken(): void {
  sessionStorage.removeItem(TOKEN_KEY);
}

/** An error answer of the API, with the problem document's `detail` as its message. */
export class ApiError extends Error {
  readonly status: number;
  readonly detail: string;
  readonly problem: Record<string, unknown> | null;

  constructor(status: number, detail: string, problem: Record<string, unknown> | null = null) {
    super(detail);
    this.name = "ApiError";
    this.status = status;
    this.detail = detail;
    this.problem = problem;
  }
}

type UnauthorizedListener = (message: string) => void;
const unauthorizedListeners = new Set<UnauthorizedListener>();

/** Called when any API call answers 401: the token is gone, the app returns to the login. */
export function onUnauthorized(listener: UnauthorizedListener): () => void {
  unauthorizedListeners.add(listener);
  return () => {
    unauthorizedListeners.delete(listener);
  };
}

export interface RequestOptions {
  method?: string;
  query?: Record<string, string | number | boolean | null | undefined>;
  json?: unknown;
  /** A raw body (a file, YAML text), sent with `contentType`. */
  body?: BodyInit;
  contentType?: string;
  /** The Accept header (default `application/json`). */
  accept?: string;
  signal?: AbortSignal;
  /** Send no token and do not treat a 401 as a lost session (the login itself). */
  anonymous?: boolean;
}

export function buildUrl(path: string, query?: RequestOptions["query"]): string {
  const params = new URLSearchParams();
  for (const [key, value] of Object.entries(query ?? {})) {
    if (value !== undefined && value !== null && value !== "") params.set(key, String(value));
  }
  const qs = params.toString();
  return qs ? `${path}?${qs}` : path;
}

/** Turn a non-2xx answer into an ApiError with a readable message. */
export async function errorFromResponse(response: Response): Promise<ApiError> {
  let problem: Record<string, unknown> | null = null;
  let detail = "";
  const text = await response.text().catch(() => "");
  try {
    const parsed: unknown = JSON.parse(text);
    if (parsed && typeof parsed === "object" && !Array.isArray(parsed)) {
      problem = parsed as Record<string, unknown>;
      if (typeof problem.detail === "string") detail = problem.detail;
      else if (typeof problem.title === "string") detail = problem.title;
    }
  } catch {
    // not JSON: fall back to the status line
  }
  if (!detail) detail = `${response.status} ${response.statusText || "error"}`.trim();
  return new ApiError(response.status, detail, problem);
}

/** Send a request and answer the raw Response of a 2xx answer (for files and text);
 * anything else is thrown as an ApiError (a 401 ends the session). */
export async function apiRequest(path: string, options: RequestOptions = {}): Promise<Response> {
  const headers: Record<string, string> = { Accept: options.accept ?? "application/json" };
  const token = options.anonymous ? null : getToken();
  if (token) headers.Authorization = `Bearer ${token}`;
  let body: BodyInit | undefined = options.body;
  if (options.json !== undefined) {
    headers["Content-Type"] = "application/json";
    body = JSON.stringify(options.json);
  } else if (body !== undefined && options.contentType) {
    headers["Content-Type"] = options.contentType;
  }
  let response: Response;
  try {
    response = await fetch(buildUrl(path, options.query), {
      method: options.method ?? "GET",
      headers,
      body,
      signal: options.signal,
    });
  } catch (err) {
    if (err instanceof DOMException && err.name === "AbortError") throw err;
    throw new ApiError(0, "The server cannot be reached. Check your connection and try again.");
  }
  if (!response.ok) {
    const error = await errorFromResponse(response);
    if (response.status === 401 && !options.anonymous) {
      clearToken();
      for (const listener of unauthorizedListeners) listener(error.detail);
    }
    throw error;
  }
  return response;
}

export async function apiFetch<T>(path: string, options: RequestOptions = {}): Promise<T> {
  const response = await apiRequest(path, options);
  if (response.status === 204) return undefined as T;
  return (await response.json()) as T;
}
