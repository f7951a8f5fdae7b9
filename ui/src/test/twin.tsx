import type { ReactElement } from "react";
import { render } from "@testing-library/react";
import { MemoryRouter, Outlet, Route, Routes } from "react-router-dom";
import type { Twin } from "../api/types";
import type { TwinContext } from "../routes/twin/context";

export function twinFixture(role: Twin["role"], overrides: Partial<Twin> = {}): Twin {
  return {
    slug: "tingen",
    id: "https://twinlink.example/tingen",
    name: "Tingen",
    url: "http://127.0.0.1:8000/twins/tingen",
    created: "2026-11-21T10:00:00Z",
    modified: "2026-11-21T10:00:00Z",
    levels: ["public"],
    role,
    document: { name: "Tingen" },
    ...overrides,
  };
}

/** Render a twin tab as the twin page does: inside a route that hands it the twin. */
export function renderTab(tab: ReactElement, twin: Twin, reload: () => void = () => {}) {
  const context: TwinContext = { slug: twin.slug, twin, reload };
  return render(
    <MemoryRouter initialEntries={[`/twins/${twin.slug}/tab`]} future={{ v7_startTransition: true, v7_relativeSplatPath: true }}>
      <Routes>
        <Route path="/twins/:slug" element={<Outlet context={context} />}>
          <Route path="tab" element={tab} />
        </Route>
      </Routes>
    </MemoryRouter>,
  );
}
