import { useState, type FormEvent } from "react";
import { updateUser } from "../../api/admin";
import { ErrorMessage } from "../common/Status";
import { useAction } from "./useAction";

const MIN_LENGTH = 8;

/** Change one's own password. The server then revokes all of the user's login sessions,
 * this one included, so the next call returns to the sign-in page. */
export function PasswordForm({ username, onChanged }: { username: string; onChanged: () => void }) {
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
    if (await action.run(() => updateUser(username, { password }))) {
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
