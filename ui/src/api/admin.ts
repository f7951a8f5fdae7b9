// Users, API tokens, a twin's roles and its devices' credentials
// (docs/api.md "Users and tokens", "Roles" and "Devices").
import { apiFetch } from "./client";
import type { Me, Schemas } from "./types";

const enc = encodeURIComponent;

// -- tokens ----------------------------------------------------------------------------------

/** What the server says about any token (never its secret nor its hash). */
export type TokenFields = Omit<Schemas["ListedToken"], "username" | "current">;

/** A token as `GET /api/v1/tokens` lists it. */
export type TokenInfo = Schemas["ListedToken"];

/** A token just created: the only answer that holds its secret. */
export type IssuedToken = Schemas["IssuedToken"] & { username?: string };

export type NewToken = Schemas["NewToken"];

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

export type NewUser = Schemas["NewUser"];

/** Only the fields given change. */
export type UserChange = Schemas["UserChange"];

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
export type DeviceWithToken = Schemas["DeviceWithToken"];

export function createDevice(slug: string, name: string, description: string): Promise<DeviceWithToken> {
  return apiFetch<DeviceWithToken>(`/api/v1/twins/${enc(slug)}/devices`, { method: "POST", json: { name, description } });
}

export function rotateDeviceToken(slug: string, device: string): Promise<DeviceWithToken> {
  return apiFetch<DeviceWithToken>(`/api/v1/twins/${enc(slug)}/devices/${enc(device)}/token`, { method: "POST" });
}

export function deleteDevice(slug: string, device: string): Promise<{ deleted: string }> {
  return apiFetch<{ deleted: string }>(`/api/v1/twins/${enc(slug)}/devices/${enc(device)}`, { method: "DELETE" });
}
