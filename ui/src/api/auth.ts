import { apiFetch } from "./client";
import type { LoginAnswer, Me } from "./types";

export function login(username: string, password: string): Promise<LoginAnswer> {
  return apiFetch<LoginAnswer>("/api/v1/auth/login", {
    method: "POST",
    json: { username, password },
    anonymous: true,
  });
}

export function logout(): Promise<unknown> {
  return apiFetch<unknown>("/api/v1/auth/logout", { method: "POST" });
}

export function getMe(signal?: AbortSignal): Promise<Me> {
  return apiFetch<Me>("/api/v1/auth/me", { signal });
}
