import { NavLink } from "react-router-dom";
import { useAuth } from "../../auth/AuthContext";
import { WorkspaceLink } from "./WorkspaceLink";

export function Header() {
  const { me, logout } = useAuth();
  return (
    <header className="header">
      <span className="brand">twinlink</span>
      <nav>
        <NavLink to="/" end>
          Catalog
        </NavLink>
        <NavLink to="/library">Library</NavLink>
        <NavLink to="/deployments">Deployments</NavLink>
        <NavLink to="/cosims">Co-simulations</NavLink>
        <NavLink to="/gateway">Gateway</NavLink>
        <NavLink to="/admin">{me?.is_admin ? "Admin" : "Account"}</NavLink>
        <WorkspaceLink />
      </nav>
      <span className="spacer" />
      {me && (
        <span className="user" title={me.groups.length ? `groups: ${me.groups.join(", ")}` : undefined}>
          {me.username}
          {me.is_admin && <span className="badge">admin</span>}
        </span>
      )}
      <button type="button" onClick={() => void logout()}>
        Log out
      </button>
    </header>
  );
}
