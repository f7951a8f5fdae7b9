import { Empty } from "../components/common/Status";

export function AdminPage() {
  return (
    <main className="page">
      <h1>Admin</h1>
      <Empty>Users, roles and tokens: coming soon.</Empty>
    </main>
  );
}
