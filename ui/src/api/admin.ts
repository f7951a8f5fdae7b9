// Users, API tokens, a twin's roles and its devices' credentials
// (docs/api.md "Users and tokens", "Roles" and "Devices").
import { apiFetch } from "./client";
import type { Device, Me } from "./types";

const enc = encodeURIComponent;

// -- tokens ----------------------------------------------------------------------------------

/** What the server says about any token (never its secret nor its hash). */
export interface TokenFields {
  id: number;
  name: string;
  state: "active" | "expired" | "revoked";
  prefix: string;
  kind: "api" | "session" | string;
  created: string;
  expires: string | null;
  last_used: string | null;
  revoked: string | null;
}

/** A token as `GET /api/v1/tokens` lists it. */
export interface TokenInfo extends TokenFields {
  /** The user the token belongs to. */
  username: string;
  /** Whether it is the token the listing was asked with: this session's. */
  current: boolean;
}

/** A token just created: the only answer that holds its secret. */
export interface IssuedToken extends TokenFields {
  token: string;
  username?: string;
}

export interface NewToken {
  name: string;
  /** Lifetime in seconds; left out, the token does not expire. */
  expires_in_s?: number;
}

export async function listTokens(all: boolean, signal?: AbortSignal): Promise<TokenInfo[]> {
  const answer = await apiFetch<{ tokens: TokenInfo[] }>("/api/v1/tokens", { query: { all: all || undefined }, signal });
  return answer.tokens;
}

export function createToken(token: NewToken): Promise<IssuedToken> {
  return apiFetch<IssuedToken>("/api/v1/tokens", { method: "POST", json: token });
}

export function createTokenFor(username: string, token: NewToken): Promise<IssuedToken> {
  return apiFetch<IssuedToken>(`/api/v1/users/${enc(username)}/tokens`, { method: "POST", json: token });
}

export function revokeToken(id: number): Promise<{ revoked: number }> {
  return apiFetch<{ revoked: number }>(`/api/v1/tokens/${id}`, { method: "DELETE" });
}

// -- users -----------------------------------------------------------------------------------

export type User = Me;

export interface NewUser {
  username: string;
  password?: string;
  is_admin: boolean;
  groups: string[];
}

/** Only the fields given change. */
export interface UserChange {
  password?: string;
  /** Needed with a new password of one's own, unless one has none yet. */
  current_password?: string;
  is_admin?: boolean;
  groups?: string[];
  disabled?: boolean;
}

export async function listUsers(signal?: AbortSignal): Promise<User[]> {
  const answer = await apiFetch<{ users: User[] }>("/api/v1/users", { signal });
  return answer.users;
}

export function createUser(user: NewUser): Promise<User> {
  return apiFetch<User>("/api/v1/users", { method: "POST", json: user });
}

export function updateUser(username: string, change: UserChange): Promise<User> {
  return apiFetch<User>(`/api/v1/users/${enc(username)}`, { method: "PATCH", json: change });
}

export function deleteUser(username: string): Promise<{ deleted: string }> {
  return apiFetch<{ deleted: string }>(`/api/v1/users/${enc(username)}`, { method: "DELETE" });
}

// -- roles -----------------------------------------------------------------------------------

export const ROLE_NAMES = ["owner", "editor", "viewer"] as const;
export type RoleName = (typeof ROLE_NAMES)[number];

export interface RoleGrant {
  username: string;
  role: RoleName;
}

export async function listRoles(slug: string, signal?: AbortSignal): Promise<RoleGrant[]> {
  const answer = await apiFetch<{ roles: RoleGrant[] }>(`/api/v1/twins/${enc(slug)}/roles`, { signal });
  return answer.roles;
}

export function setRole(slug: string, username: string, role: RoleName): Promise<RoleGrant> {
  return apiFetch<RoleGrant>(`/api/v1/twins/${enc(slug)}/roles/${enc(username)}`, { method: "PUT", json: { role } });
}

export function removeRole(slug: string, username: string): Promise<unknown> {
  return apiFetch<unknown>(`/api/v1/twins/${enc(slug)}/roles/${enc(username)}`, { method: "DELETE" });
}

// -- devices ---------------------------------------------------------------------------------

/** A device just created or given a new token: the only answer that holds the token. */
export interface DeviceWithToken extends Device {
  token: string;
}

export function createDevice(slug: string, name: string, description: string): Promise<DeviceWithToken> {
  return apiFetch<DeviceWithToken>(`/api/v1/twins/${enc(slug)}/devices`, { method: "POST", json: { name, description } });
}

export function rotateDeviceToken(slug: string, device: string): Promise<DeviceWithToken> {
  return apiFetch<DeviceWithToken>(`/api/v1/twins/${enc(slug)}/devices/${enc(device)}/token`, { method: "POST" });
}

export function deleteDevice(slug: string, device: string): Promise<{ deleted: string }> {
  return apiFetch<{ deleted: string }>(`/api/v1/twins/${enc(slug)}/devices/${enc(device)}`, { method: "DELETE" });
}
