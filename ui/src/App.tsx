import { Navigate, Outlet, Route, Routes, useLocation } from "react-router-dom";
import { AuthProvider, useAuth } from "./auth/AuthContext";
import { Header } from "./components/layout/Header";
import { Empty } from "./components/common/Status";
import { CatalogPage } from "./routes/CatalogPage";
import { GatewayPage } from "./routes/GatewayPage";
import { LoginPage } from "./routes/LoginPage";
import { AdminPage } from "./routes/AdminPage";
import { LibraryPage } from "./routes/LibraryPage";
import { DeploymentsPage } from "./routes/DeploymentsPage";
import { DeploymentPage } from "./routes/DeploymentPage";
import { CosimsPage } from "./routes/CosimsPage";
import { CosimPage } from "./routes/CosimPage";
import { TwinPage } from "./routes/twin/TwinPage";
import { OverviewTab } from "./routes/twin/OverviewTab";
import { LiveTab } from "./routes/twin/LiveTab";
import { HistoryTab } from "./routes/twin/HistoryTab";
import { CommandsTab } from "./routes/twin/CommandsTab";
import { ProcessorsTab } from "./routes/twin/ProcessorsTab";
import { DocumentTab } from "./routes/twin/DocumentTab";

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
        <Route path="twins/:slug" element={<TwinPage />}>
          <Route index element={<OverviewTab />} />
          <Route path="live" element={<LiveTab />} />
          <Route path="history" element={<HistoryTab />} />
          <Route path="commands" element={<CommandsTab />} />
          <Route path="processors" element={<ProcessorsTab />} />
          <Route path="document" element={<DocumentTab />} />
        </Route>
        <Route path="library" element={<LibraryPage />} />
        <Route path="deployments" element={<DeploymentsPage />} />
        <Route path="deployments/:name" element={<DeploymentPage />} />
        <Route path="cosims" element={<CosimsPage />} />
        <Route path="cosims/:id" element={<CosimPage />} />
        <Route path="gateway" element={<GatewayPage />} />
        <Route path="admin" element={<AdminPage />} />
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
