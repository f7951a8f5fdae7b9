import { getMe } from "../api/auth";
import { useAuth } from "../auth/AuthContext";
import { AccountSection } from "../components/admin/AccountSection";
import { PasswordForm } from "../components/admin/PasswordForm";
import { TokensSection } from "../components/admin/TokensSection";
import { UsersSection } from "../components/admin/UsersSection";
import { ErrorMessage, Loading } from "../components/common/Status";
import { useApi } from "../hooks/useApi";
import "../components/admin/admin.css";

/** Everyone's account, password and tokens; for admins also users and every user's tokens. */
export function AdminPage() {
  const { logout } = useAuth();
  // Asked afresh (not only the header's copy), so a failure is shown rather than waited on.
  const account = useApi((signal) => getMe(signal), []);
  const me = account.data;

  // After a password change this session is revoked: any call answers 401, and the app's
  // 401 handling returns to the sign-in page saying the session has ended. Should the
  // session still work, sign out the ordinary way.
  async function toSignIn() {
    try {
      await getMe();
    } catch {
      return;
    }
    await logout();
  }
  if (!me) {
    return (
      <main className="page">
        <h1>Account</h1>
        {account.error ? <ErrorMessage error={account.error} onRetry={account.reload} /> : <Loading what="Loading your account" />}
      </main>
    );
  }
  return (
    <main className="page">
      <h1>{me.is_admin ? "Admin" : "Account"}</h1>
      <h2>Your account</h2>
      <AccountSection me={me} />
      <h3>Change your password</h3>
      <PasswordForm username={me.username} onChanged={() => void toSignIn()} />
      <h2>Your tokens</h2>
      <TokensSection />
      {me.is_admin && (
        <>
          <h2>Users</h2>
          <UsersSection me={me.username} />
          <h2>All tokens</h2>
          <TokensSection all />
        </>
      )}
    </main>
  );
}
