import { useState, type FormEvent } from "react";
import { updateUser } from "../../api/admin";
import { ApiError } from "../../api/client";
import { ErrorMessage } from "../common/Status";
import { useAction } from "./useAction";

const MIN_LENGTH = 8;

/** Left empty, no current password is sent: the server then says that one is needed (shown
 * in the form's words), or, for a user without a password, sets the first one. */
async function changePassword(username: string, password: string, current: string): Promise<void> {
  try {
    await updateUser(username, current ? { password, current_password: current } : { password });
  } catch (err) {
    if (!current && err instanceof ApiError && err.status === 422) {
      throw new Error("Enter your current password: it is needed to change it.");
    }
    throw err;
  }
}

/** Change one's own password: the server asks for the current one (unless the user has none
 * yet, signing in with tokens only), then revokes all of the user's login sessions, this one
 * included, so the next call returns to the sign-in page. */
export function PasswordForm({ username, onChanged }: { username: string; onChanged: () => void }) {
  const [current, setCurrent] = useState("");
  const [password, setPassword] = useState("");
  const [repeat, setRepeat] = useState("");
  const [done, setDone] = useState(false);
  const action = useAction();
  const mismatch = repeat.length > 0 && password !== repeat;

  async function submit(event: FormEvent) {
    event.preventDefault();
    if (password.length < MIN_LENGTH) {
      action.setError(new Error(`The password needs at least ${MIN_LENGTH} characters.`));
      return;
    }
    if (password !== repeat) {
      action.setError(new Error("The two passwords differ."));
      return;
    }
    if (await action.run(() => changePassword(username, password, current))) {
      setCurrent("");
      setPassword("");
      setRepeat("");
      setDone(true);
    }
  }

  if (done) {
    return (
      <div className="notice" role="status">
        <p>Your password has been changed. Every login session of yours has ended, this one too: sign in again with the new password.</p>
        <button type="button" onClick={onChanged}>
          Sign in again
        </button>
      </div>
    );
  }
  return (
    <form className="stack-form" onSubmit={(e) => void submit(e)} aria-label="Change your password">
      <p className="notice">Changing your password signs you out everywhere: all your login sessions end, this one too. Your API tokens keep working.</p>
      <label>
        Current password
        <input type="password" autoComplete="current-password" value={current} onChange={(e) => setCurrent(e.target.value)} />
      </label>
      <span className="muted">Leave it empty only if your account has no password yet (you signed in with a token).</span>
      <label>
        New password
        <input type="password" autoComplete="new-password" value={password} onChange={(e) => setPassword(e.target.value)} />
      </label>
      <label>
        Repeat the new password
        <input type="password" autoComplete="new-password" value={repeat} onChange={(e) => setRepeat(e.target.value)} />
      </label>
      {mismatch && <span className="muted">The two passwords differ.</span>}
      {action.error && <ErrorMessage error={action.error} />}
      <div>
        <button type="submit" disabled={action.busy || !password || mismatch}>
          Change password
        </button>
      </div>
    </form>
  );
}
