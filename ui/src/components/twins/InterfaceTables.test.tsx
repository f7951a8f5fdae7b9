import { describe, expect, it } from "vitest";
import { render, screen, within } from "@testing-library/react";
import { InterfaceTables, rangeText } from "./InterfaceTables";

const document = {
  interface: {
    default_device: "plc",
    signals: [{ name: "Cantilever_Angle_radians", unit: "rad", type: "number", min: 0, max: 1, description: "Tip angle." }],
    properties: [{ name: "sample_rate", type: "number", unit: "Hz", min: 1, max: 100, writable: true }],
    commands: [
      { name: "pause", description: "Stop sending.", parameters: [] },
      { name: "set_sample_rate", parameters: [{ name: "value", type: "number", unit: "Hz", min: 1, max: 100, required: true }] },
    ],
  },
};

describe("InterfaceTables", () => {
  it("shows signals, properties and commands with their parameters as tables", () => {
    render(<InterfaceTables document={document} />);
    const signals = screen.getByRole("table", { name: "Signals" });
    const row = within(signals).getByText("Cantilever_Angle_radians").closest("tr")!;
    expect(Array.from(row.cells).map((c) => c.textContent)).toEqual(["Cantilever_Angle_radians", "number", "rad", "0 – 1", "Tip angle."]);
    const properties = screen.getByRole("table", { name: "Properties" });
    expect(within(properties).getByText("sample_rate").closest("tr")).toHaveTextContent("yes");
    const commands = screen.getByRole("table", { name: "Commands" });
    expect(within(commands).getByText("pause").closest("tr")).toHaveTextContent("none");
    expect(within(commands).getByText("set_sample_rate").closest("tr")).toHaveTextContent("value (number, Hz, 1 – 100, required)");
    expect(screen.getByText(/Commands go to the device/)).toHaveTextContent("plc");
    // no JSON anywhere
    expect(screen.queryByText(/[{}"]/)).not.toBeInTheDocument();
  });

  it("says nothing for a twin without an interface, and writes ranges readably", () => {
    const { container } = render(<InterfaceTables document={{}} />);
    expect(container).toBeEmptyDOMElement();
    expect(rangeText({ min: 1 })).toBe("≥ 1");
    expect(rangeText({ max: 2.5 })).toBe("≤ 2.5");
    expect(rangeText({})).toBe("");
  });
});
