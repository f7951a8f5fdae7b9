import { describe, expect, it } from "vitest";
import { render, screen, within } from "@testing-library/react";
import { DocumentDetails, numberText } from "./DocumentDetails";

describe("DocumentDetails", () => {
  it("writes numbers as the document's YAML does", () => {
    expect(numberText(2.1e11)).toBe("2.1e11");
    expect(numberText(-3e9)).toBe("-3e9");
    expect(numberText(1795673707)).toBe("1795673707");
    expect(numberText(7850)).toBe("7850");
    expect(numberText(2.1e-12)).toBe("2.1e-12");
    expect(numberText(9.72)).toBe("9.72");
  });

  it("shows entries of one shape as a table and other mappings nested, never as JSON", () => {
    render(
      <DocumentDetails
        document={{
          physicalProperties: { youngsModulus: { value: 2.1e11, unit: "Pa" }, tipMass: { value: null, unit: "kg" } },
          contact: { name: "Rig contact", email: "rig@example.org" },
          checks: [{ what: "torque", ok: true }],
        }}
      />,
    );
    const table = screen.getByRole("table");
    const row = within(table).getByRole("rowheader", { name: "youngsModulus" }).closest("tr")!;
    expect(Array.from(row.cells).map((c) => c.textContent)).toEqual(["youngsModulus", "2.1e11", "Pa"]);
    expect(within(table).getByRole("rowheader", { name: "tipMass" }).closest("tr")).toHaveTextContent("null");
    expect(screen.getByText("rig@example.org")).toBeInTheDocument();
    expect(screen.getByText("torque").closest("ol")).toHaveClass("nested-list");
  });
});
