// The API's answers, named for the app. Each is a type of openapi.ts, which is generated from
// the server's /openapi.json (npm run api-types): never written twice by hand. Only the DT
// document's fields are typed here, since the API carries the document as any JSON object.
import type { components } from "./openapi";

/** A schema of the API description by its name. */
export type Schemas = components["schemas"];

export type Me = Schemas["UserView"];
export type LoginAnswer = Schemas["LoginAnswer"];
export type TwinSummary = Schemas["TwinSummary"];
export type TwinPage = Schemas["TwinPage"];
export type RelationNode = Schemas["RelationNode"];
/** A twin of another instance a relation names (docs/federation.md). */
export type RemoteSummary = Schemas["RemoteSummary"];
export type Device = Schemas["DeviceState"];
export type SearchMatch = Schemas["Match"];
export type SearchHit = Schemas["Hit"];
export type SearchAnswer = Schemas["SearchAnswer"];
export type ServiceHealth = Schemas["Health"];
export type Service = Schemas["ServiceView"];
/** A service's figures since the server started. */
export type ServiceStats = Schemas["ServiceStats"];
export type AuditEntry = Schemas["AuditEntry"];

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

/** A twin as the caller may see it, its document typed. */
export type Twin = Omit<Schemas["Twin"], "document"> & { document: TwinDocument };
