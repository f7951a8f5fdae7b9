import { describe, expect, it } from "vitest";
import { render, screen, within } from "@testing-library/react";
import type { Plan } from "../../api/deployments";
import { PlanView, planSummary, showPlanValue } from "./PlanView";

const plan: Plan = {
  create: [
    { type: "twin", name: "rig-a", spec: { document: {} } },
    { type: "device", name: "tingenSAP", spec: { name: "tingenSAP" } },
    { type: "processor", name: "fmu", spec: { blueprint: "fmu", params: { parameters: { zeta: 0.9 } } } },
  ],
  update: [{ type: "processor", name: "filter", changes: [{ path: "params.cutoff_hz", from: 5, to: 2.5 }, { path: "enabled", from: null, to: true }] }],
  delete: [{ type: "connector", name: "opcua" }],
  keep: [{ type: "service", name: "historian" }],
};

describe("PlanView", () => {
  it("lists what is created, updated, deleted and kept, with each change's old and new value", () => {
    render(<PlanView plan={plan} />);
    expect(screen.getByText("3 to create, 1 to update, 1 to delete", { exact: false })).toBeInTheDocument();
    const create = screen.getByRole("list", { name: "Create" });
    expect(within(create).getAllByRole("listitem").map((li) => li.textContent?.replace(/Specification.*/s, ""))).toEqual([
      "+ twin rig-a",
      "+ device tingenSAP",
      "+ processor fmu",
    ]);
    const update = screen.getByRole("list", { name: "Update" });
    expect(within(update).getByText("params.cutoff_hz").parentElement).toHaveTextContent("params.cutoff_hz: 5 → 2.5");
    expect(within(update).getByText("enabled").parentElement).toHaveTextContent("enabled: none → true");
    expect(within(screen.getByRole("list", { name: "Delete" })).getByText("opcua")).toBeInTheDocument();
    expect(within(screen.getByRole("list", { name: "Keep" })).getByText("historian")).toBeInTheDocument();
  });

  it("shows a processor's specification as it will be created, the parameters filled in", () => {
    render(<PlanView plan={plan} />);
    const fmu = screen.getByText("fmu").closest("li")!;
    expect(within(fmu).getByText(/"zeta": 0.9/)).toBeInTheDocument();
  });

  it("says when there is nothing to do", () => {
    render(<PlanView plan={{ create: [], update: [], delete: [], keep: [{ type: "twin", name: "rig-a" }] }} />);
    expect(screen.getByText("Nothing to do.")).toBeInTheDocument();
    expect(screen.queryByRole("list", { name: "Create" })).toBeNull();
  });

  it("writes values and counts as people read them", () => {
    expect(showPlanValue(undefined)).toBe("none");
    expect(showPlanValue("text")).toBe("text");
    expect(showPlanValue({ a: [1, 2] })).toBe('{"a":[1,2]}');
    expect(planSummary({ create: [], update: [], delete: [], keep: [] })).toBe("0 to create, 0 to update, 0 to delete");
  });
});
