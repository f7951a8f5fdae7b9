import { createContext, useCallback, useContext, useEffect, useMemo, useState, type ReactNode } from "react";
import * as authApi from "../api/auth";
import { clearToken, getToken, onUnauthorized, setToken } from "../api/client";
import type { Me } from "../api/types";

interface AuthValue {
  token: string | null;
  me: Me | null;
  /** Why the user was sent back to the login, e.g. an expired token. */
  notice: string | null;
  login: (username: string, password: string) => Promise<void>;
  logout: () => Promise<void>;
}

const AuthContext = createContext<AuthValue | null>(null);

export function AuthProvider({ children }: { children: ReactNode }) {
  const [token, setTokenState] = useState<string | null>(() => getToken());
  const [me, setMe] = useState<Me | null>(null);
  const [notice, setNotice] = useState<string | null>(null);

  useEffect(
    () =>
      onUnauthorized((detail) => {
        setTokenState(null);
        setMe(null);
        setNotice(`Your session has ended; please sign in again. (${detail})`);
      }),
    [],
  );

  useEffect(() => {
    if (!token) return;
    const controller = new AbortController();
    authApi
      .getMe(controller.signal)
      .then(setMe)
      .catch(() => {
        // a 401 is handled by onUnauthorized; other errors leave the name out of the header
      });
    return () => controller.abort();
  }, [token]);

  const login = useCallback(async (username: string, password: string) => {
    const answer = await authApi.login(username, password);
    setToken(answer.token);
    setNotice(null);
    setTokenState(answer.token);
  }, []);

  const logout = useCallback(async () => {
    try {
      await authApi.logout();
    } catch {
      // the token may be gone already; sign out locally anyway
    }
    clearToken();
    setTokenState(null);
    setMe(null);
    setNotice("You have signed out.");
  }, []);

  const value = useMemo(() => ({ token, me, notice, login, logout }), [token, me, notice, login, logout]);
  return <AuthContext.Provider value={value}>{children}</AuthContext.Provider>;
}

export function useAuth(): AuthValue {
  const value = useContext(AuthContext);
  if (!value) throw new Error("useAuth outside AuthProvider");
  return value;
}
