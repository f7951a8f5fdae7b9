export interface Me {
  username: string;
  is_admin: boolean;
  groups: string[];
  disabled: boolean;
  created: string;
}

export interface LoginAnswer {
  token: string;
  token_type: string;
  expires: string | null;
}

export interface TwinSummary {
  slug: string;
  id: string;
  name: string;
  url: string;
  created: string;
  modified: string;
  levels: string[];
}

export interface TwinPage {
  items: TwinSummary[];
  next_cursor: string | null;
}

export interface Feature {
  name: string;
  description?: string;
  address?: string;
  apiAddress?: string;
  documentation?: string;
  requirement?: string;
  protocol?: string;
  keywords?: string[];
  [key: string]: unknown;
}

export interface Relation {
  relationType?: string;
  id?: string;
  [key: string]: unknown;
}

export interface TwinDocument {
  version?: string;
  privacy?: string;
  id?: string;
  name?: string;
  description?: string;
  owner?: string;
  manufacturer?: string;
  features?: Feature[];
  relations?: Relation[];
  [key: string]: unknown;
}

export interface Twin extends TwinSummary {
  role: "owner" | "editor" | "viewer" | "admin" | null;
  document: TwinDocument;
}

export interface RelationNode {
  id: string;
  slug?: string;
  name?: string;
  registered?: boolean;
  nodes: RelationNode[];
}

export interface Device {
  name: string;
  twin: string;
  description?: string | null;
  token_prefix?: string;
  created: string;
  last_seen: string | null;
  connected?: boolean;
}

export interface SearchMatch {
  feature: string | null;
  privacy: string;
  snippet: string;
}

export interface SearchHit {
  slug: string;
  name: string;
  score: number;
  matches: SearchMatch[];
}

export interface SearchAnswer {
  query: string;
  keyword: string | null;
  total: number;
  limit: number;
  offset: number;
  hits: SearchHit[];
  facets?: { keywords: { value: string; count: number }[]; counted_hits?: number };
}

export interface ServiceHealth {
  checked_at: number;
  path: string | null;
  status: "up" | "down";
  http_status: number | null;
  ms: number;
  error?: string;
}

export interface Service {
  name: string;
  twin: string;
  source: "document" | "api";
  base_url: string;
  feature: string | null;
  description: string | null;
  auth: { method: string; [key: string]: unknown };
  methods: string[];
  health_path: string | null;
  blocked: string | null;
  gateway_path: string;
  health: ServiceHealth | null;
  requests: number;
  stats?: ServiceStats;
  credential_refreshes: number;
  credential_error: string | null;
}

/** A service's figures since the server started. */
export interface ServiceStats {
  statuses: Record<string, number>;
  failures: Record<string, number>;
  bytes_in: number;
  bytes_out: number;
  upstream_ms: { mean: number; p50: number | null; p95: number | null } | null;
}

export interface AuditEntry {
  id: number;
  time: number;
  time_iso: string;
  twin: string;
  service: string;
  caller: string;
  method: string;
  path: string;
  status: number;
  outcome: string;
  bytes_in: number;
  bytes_out: number;
  upstream_ms: number | null;
  total_ms: number;
}
