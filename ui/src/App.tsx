import { Navigate, Outlet, Route, Routes, useLocation } from "react-router-dom";
import { AuthProvider, useAuth } from "./auth/AuthContext";
import { Header } from "./components/layout/Header";
import { Empty } from "./components/common/Status";
import { CatalogPage } from "./routes/CatalogPage";
import { GatewayPage } from "./routes/GatewayPage";
import { LoginPage } from "./routes/LoginPage";
import { TwinPage } from "./routes/TwinPage";

function SignedIn() {
  const { token } = useAuth();
  const location = useLocation();
  if (!token) return <Navigate to="/login" replace state={{ from: location.pathname + location.search }} />;
  return (
    <>
      <Header />
      <Outlet />
    </>
  );
}

export function AppRoutes() {
  return (
    <Routes>
      <Route path="/login" element={<LoginPage />} />
      <Route element={<SignedIn />}>
        <Route index element={<CatalogPage />} />
        <Route path="twins/:slug" element={<TwinPage />} />
        <Route path="gateway" element={<GatewayPage />} />
        <Route path="*" element={<main className="page"><Empty>There is no such page.</Empty></main>} />
      </Route>
    </Routes>
  );
}

export function App() {
  return (
    <AuthProvider>
      <AppRoutes />
    </AuthProvider>
  );
}
