import { useState } from "react";
import { createToken, listTokens, revokeToken, type IssuedToken, type NewToken, type TokenInfo } from "../../api/admin";
import { useApi } from "../../hooks/useApi";
import { Empty, ErrorMessage, Loading } from "../common/Status";
import { CreateTokenForm } from "./CreateTokenForm";
import { SecretOnce } from "./SecretOnce";
import { TokenTable } from "./TokenTable";
import { useAction } from "./useAction";

function revokeQuestion(t: TokenInfo): string {
  if (t.current) {
    return `Revoke "${t.name}"? It is the token of this session: you will be signed out at once and have to sign in again.`;
  }
  const whose = t.username ? ` of ${t.username}` : "";
  return `Revoke the token "${t.name}"${whose} (${t.prefix}…)? Anything that uses it stops working at once.`;
}

/** The caller's tokens, or with `all` every user's (admins), with revoking; the caller's own
 * list also creates tokens. A new secret lives only in this component's state. */
export function TokensSection({ all = false }: { all?: boolean }) {
  const tokens = useApi((signal) => listTokens(all, signal), [all]);
  const [issued, setIssued] = useState<IssuedToken>();
  const action = useAction();

  const create = (token: NewToken) =>
    action.run(async () => {
      setIssued(await createToken(token));
      tokens.reload();
    });
  const revoke = (t: TokenInfo) => {
    if (!window.confirm(revokeQuestion(t))) return;
    void action.run(async () => {
      await revokeToken(t.id);
      tokens.reload();
    });
  };

  return (
    <>
      {all ? (
        <p className="muted section-note">Every user&apos;s login sessions and API tokens.</p>
      ) : (
        <p className="muted section-note">Login sessions and API tokens for scripts. A token acts with your rights until it expires or is revoked.</p>
      )}
      {issued && <SecretOnce title={`Your new token "${issued.name}"`} secret={issued.token} onDone={() => setIssued(undefined)} />}
      {action.error && <ErrorMessage error={action.error} />}
      {tokens.error ? (
        <ErrorMessage error={tokens.error} onRetry={tokens.reload} />
      ) : !tokens.data ? (
        <Loading />
      ) : tokens.data.length === 0 ? (
        <Empty>No tokens.</Empty>
      ) : (
        <TokenTable tokens={tokens.data} showUser={all} busy={action.busy} onRevoke={revoke} />
      )}
      {!all && <CreateTokenForm busy={action.busy} label="Create a token" onCreate={create} />}
    </>
  );
}
